// The experiment specification (docs/api.md, docs/spec.md): defaults, normalisation, errors that name the field,
// and the result formats (curve.csv header, summary.json keys).
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "engine/contact/pair_kernel.h"
#include "api/curve_format.h"
#include "api/runner.h"
#include "api/spec.h"
#include "engine/model/model.h"
#include "api/summary_json.h"
#include "engine/experiments/crystal_compression/crystal_compression_experiment.h"
#include "engine/experiments/crystal_confinement/crystal_confinement.h"
#include "engine/experiments/crystal_shear/crystal_shear_experiment.h"
#include "engine/experiments/two_cube_sliding/two_cube_sliding_experiment.h"
#include "api/spec_error.h"

namespace granulab::api {
namespace {

using nlohmann::json;

// Copied verbatim from the product contract's example spec (the one every README and client started from).
constexpr const char* kContractCrystalExample = R"({
  "experiment": "crystal_compression",
  "label": "ref p0=60kPa",
  "grain":    {"shape": "rhombic_dodecahedron", "size": 0.01, "edge_spheres": 10, "overlap": 0.75},
  "material": {"youngs_modulus": 3.0e9, "density": 1200, "friction": 0.35,
               "tangential_stiffness_ratio": 0.2857, "damping": 0.05},
  "crystal":  {"grains_x": 8, "rows_z": 18, "layers_y": 6, "knockout": []},
  "loading":  {"confining_pressure": 60e3, "max_strain": 0.1, "rate_number": 1e-4, "mass_scaling": 1.0},
  "output":   {"curve_points": 400, "snapshot_strains": [0.0, 0.01, 0.02, 0.04, 0.08]},
  "run":      {"threads": 0}
})";

// ---------------------------------------------------------------------------------------------
// 1. Valid specs and their defaults

TEST(SpecDefaults, TwoCubeSlidingGetsThePaperDefaults) {
  const Spec spec = parse_spec_text(R"({"experiment": "two_cube_sliding"})");
  EXPECT_STREQ(spec.name(), "two_cube_sliding");
  EXPECT_EQ(spec.label, "");
  EXPECT_EQ(spec.threads, 0);
  const TwoCubeParams& tc = spec.as<TwoCubeSlidingExperiment>().params;
  EXPECT_EQ(tc.grain.shape, Shape::cube);
  EXPECT_DOUBLE_EQ(tc.grain.size, 0.01);
  EXPECT_EQ(tc.grain.edge_spheres, 10);
  EXPECT_DOUBLE_EQ(tc.grain.overlap, 0.75);
  EXPECT_DOUBLE_EQ(tc.material.friction, 0.3);
  EXPECT_DOUBLE_EQ(tc.material.youngs_modulus, 3.0e9);
  EXPECT_DOUBLE_EQ(tc.material.density, 1200);
  EXPECT_DOUBLE_EQ(tc.prestrain, 0.005);
  EXPECT_DOUBLE_EQ(tc.max_slide, 0.8);
  EXPECT_EQ(tc.curve_points, 400);
}

TEST(SpecDefaults, EmptyObjectIsTwoCubeSliding) {
  const Spec empty = parse_spec_text("{}");
  EXPECT_STREQ(empty.name(), "two_cube_sliding");
  EXPECT_EQ(empty.normalized.at("experiment"), "two_cube_sliding");
  const Spec named = parse_spec_text(R"({"experiment": "two_cube_sliding"})");
  EXPECT_EQ(empty.normalized, named.normalized);
}

TEST(SpecDefaults, NullValuesMeanTheDefault) {
  const Spec spec = parse_spec_text(R"({"label": null, "grain": null, "material": {"friction": null}})");
  EXPECT_EQ(spec.normalized, parse_spec_text("{}").normalized);
}

// A NUL byte ends nlohmann's input: a document followed by one and garbage must not pass.
TEST(SpecErrors, NulBytesAreInvalidJsonWhereverTheyAre) {
  for (const std::string& text :
       {std::string("{}\0", 3), std::string("{}\0garbage", 10), std::string("{\"label\": \"a\0b\"}", 15)}) {
    try {
      parse_spec_text(text);
      ADD_FAILURE() << "accepted a NUL byte";
    } catch (const SpecError& e) {
      EXPECT_EQ(e.code, "invalid_json");
    }
  }
}

// The label's limit is in characters: 200 accented letters are 400 bytes and fit; 201 do not.
TEST(SpecErrors, LabelLengthCountsCharactersNotBytes) {
  std::string label;
  for (int k = 0; k < 200; ++k) label += "\xc3\xa9";  // é
  EXPECT_EQ(parse_spec_text(R"({"label": ")" + label + R"("})").label, label);
  EXPECT_THROW(parse_spec_text(R"({"label": ")" + label + "x" + R"("})"), SpecError);
}

// A key given twice is refused (which one would count is a guess), naming it, at any depth.
TEST(SpecErrors, DuplicateKeysAreRefusedNamingTheField) {
  for (const auto& [text, field] : std::vector<std::pair<std::string, std::string>>{
           {R"({"grain": {"edge_spheres": 3, "edge_spheres": 4}})", "grain.edge_spheres"},
           {R"({"label": "a", "label": "a"})", "label"},
           {R"({"grain": {}, "grain": {}})", "grain"}}) {
    try {
      parse_spec_text(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const SpecError& e) {
      EXPECT_EQ(e.code, "duplicate_field") << text;
      EXPECT_EQ(e.field, field) << text;
    }
  }
}

// run.kernel forces a contact kernel: one of the binary's, which this CPU runs; else a 400 naming the field.
TEST(SpecErrors, KernelIsOneThisCpuRuns) {
  for (const char* experiment : {"two_cube_sliding", "crystal_compression"}) {
    const std::string head = std::string(R"({"experiment": ")") + experiment + R"(", "run": {"kernel": )";
    try {
      parse_spec_text(head + R"("avx3"}})");
      ADD_FAILURE() << "accepted kernel avx3";
    } catch (const SpecError& e) {
      EXPECT_EQ(e.field, "run.kernel");
      EXPECT_NE(std::string(e.what()).find(kBaselineKernel), std::string::npos) << e.what();
    }
    for (const PairKernelInfo& k : pair_kernels()) {
      const std::string text = head + "\"" + k.name + "\"}}";
      if (k.runs_here) {
        EXPECT_EQ(parse_spec_text(text).normalized["run"]["kernel"], k.name);
        continue;
      }
      try {
        parse_spec_text(text);
        ADD_FAILURE() << "accepted kernel " << k.name << ", which this CPU lacks";
      } catch (const SpecError& e) {
        EXPECT_EQ(e.field, "run.kernel");
        EXPECT_NE(std::string(e.what()).find("lacks"), std::string::npos) << e.what();
      }
    }
  }
}

TEST(SpecDefaults, ExplicitValuesAreTaken) {
  const Spec spec = parse_spec_text(R"({"label": "run A",
      "grain": {"size": 0.02, "edge_spheres": 12.0, "overlap": 0.5},
      "material": {"friction": 0.5},
      "loading": {"prestrain": 0.01, "max_slide": 1.0},
      "output": {"curve_points": 50}, "run": {"threads": 4}})");
  EXPECT_EQ(spec.label, "run A");
  EXPECT_EQ(spec.threads, 4);
  EXPECT_DOUBLE_EQ(spec.as<TwoCubeSlidingExperiment>().params.grain.size, 0.02);
  EXPECT_EQ(spec.as<TwoCubeSlidingExperiment>().params.grain.edge_spheres, 12);  // 12.0 is an integer value
  EXPECT_DOUBLE_EQ(spec.as<TwoCubeSlidingExperiment>().params.grain.overlap, 0.5);
  EXPECT_DOUBLE_EQ(spec.as<TwoCubeSlidingExperiment>().params.material.friction, 0.5);
  EXPECT_DOUBLE_EQ(spec.as<TwoCubeSlidingExperiment>().params.prestrain, 0.01);
  EXPECT_DOUBLE_EQ(spec.as<TwoCubeSlidingExperiment>().params.max_slide, 1.0);
  EXPECT_EQ(spec.as<TwoCubeSlidingExperiment>().params.curve_points, 50);
}

TEST(SpecDefaults, RangeBoundariesAreAccepted) {
  // Closed ends are allowed; edge_spheres 2 and 40, overlap 0 and 0.95, friction 0.
  for (const char* text :
       {R"({"grain": {"edge_spheres": 2}})", R"({"grain": {"edge_spheres": 40}})", R"({"grain": {"overlap": 0}})",
        R"({"grain": {"overlap": 0.95}})", R"({"material": {"friction": 0}})", R"({"loading": {"prestrain": 0.1}})"}) {
    SCOPED_TRACE(text);
    EXPECT_NO_THROW(parse_spec_text(text));
  }
}

TEST(SpecDefaults, ContractCrystalExampleParses) {
  const Spec spec = parse_spec_text(kContractCrystalExample);
  EXPECT_STREQ(spec.name(), "crystal_compression");
  EXPECT_EQ(spec.label, "ref p0=60kPa");
  EXPECT_EQ(spec.normalized.at("experiment"), "crystal_compression");
  EXPECT_EQ(spec.normalized.at("grain").at("shape"), "rhombic_dodecahedron");
  EXPECT_EQ(spec.normalized.at("crystal").at("rows_z"), 18);
  EXPECT_EQ(spec.normalized.at("crystal").at("knockout"), json::array());
  EXPECT_EQ(spec.normalized.at("output").at("snapshot_strains"), json({0.0, 0.01, 0.02, 0.04, 0.08}));
  EXPECT_DOUBLE_EQ(spec.normalized.at("loading").at("confining_pressure").get<double>(), 60e3);
}

// The interface law by default: the paper's (docs/model.md, "Interface laws"); k_N of hertz 4/3 E* of E = 3 GPa,
// nu = 0.3.
const json kDefaultContact = {{"normal", "hooke"},
                              {"tangential", "linear_history"},
                              {"poisson_ratio", 0.3},
                              {"surface_energy", 0.0},
                              {"hertz_stiffness", 4.0 / 3 * effective_modulus(3.0e9, 0.3)}};

TEST(SpecDefaults, CrystalDefaultsAreTheContractExample) {
  // "Every field has the paper's default": the bare crystal spec normalises to the contract example
  // (label empty, k_t/k_n the exact 2/7 that the example rounds to 0.2857).
  json expected = json::parse(kContractCrystalExample);
  expected["label"] = "";
  expected["material"]["tangential_stiffness_ratio"] = 2.0 / 7;
  // Deliberate departures: the default rate is the one shown quasi-static, 1.5 p0 / E (docs/results.md,
  // "Quasi-static rate"), not the example's 1e-4, and knock-out regions normalise to an empty list.
  expected["loading"]["rate_number"] = 1.5 * 60e3 / 3e9;
  expected["crystal"]["knockout_regions"] = json::array();
  expected["loading"]["wall_friction"] = 0.35;      // an extension: the platens' f, by default the grains'
  expected["loading"]["confinement"] = "membrane";  // extensions: the bag, and no loading program
  expected["loading"]["program"] = json::array();
  expected["imperfections"] = {{"size_dispersion", 0.0}, {"misorientation", 0.0}, {"seed", 1}};  // perfect grains
  // Extensions: the lattice and the loading axis, by default the paper's FCC off-axis crystal.
  expected["crystal"]["lattice"] = "fcc";
  expected["loading"]["axis"] = json::array({-1.0, -1.0, 2.0});
  expected["loading"]["lateral"] = json::array();
  expected["output"]["stress_drop_threshold"] = 0.02;  // an extension: the stick-slip events' depth, over p0
  expected["contact"] = kDefaultContact;               // an extension: the paper's law, hooke + linear_history
  const Spec spec = parse_spec_text(R"({"experiment": "crystal_compression"})");
  json got = spec.normalized;
  // Engine knobs that are not in the contract example.
  got["run"].erase("time_step_factor");
  got["run"].erase("skin_factor");
  // An extension: the grains' local damping, off by default (the paper's model).
  expected["run"]["local_damping"] = 0.0;
  expected["run"]["local_damping_rotational"] = 0.0;
  // An extension: which velocity the dashpots see; the quarter step lets the default time step be 0.3 t0.
  expected["run"]["damping_velocity"] = "quarter_step";
  expected["run"]["kernel"] = "auto";  // an extension: the contact kernel, the widest this CPU runs
  EXPECT_EQ(got, expected) << got.dump(2);
}

// ---------------------------------------------------------------------------------------------
// 2. The normalised spec

// The default rate follows the spec's own p0 and E, and a given rate is kept as given.
// The lattice picks the grain and the default axis; HCP takes the four-index form (U, V, T, W) -> (U - T, V - T, W).
TEST(SpecDefaults, LatticeAndAxisFollowEachOther) {
  const Spec sc = parse_spec_text(R"({"experiment": "crystal_compression", "crystal": {"lattice": "sc"}})");
  EXPECT_EQ(sc.normalized.at("grain").at("shape"), "cube");
  EXPECT_EQ(sc.normalized.at("loading").at("axis"), json({0.0, 0.0, 1.0}));
  const Spec hcp = parse_spec_text(
      R"({"experiment": "crystal_compression", "crystal": {"lattice": "hcp"}, "loading": {"axis": [2, -1, -1, 0]}})");
  EXPECT_EQ(hcp.normalized.at("grain").at("shape"), "trapezo_rhombic_dodecahedron");
  EXPECT_EQ(hcp.normalized.at("loading").at("axis"), json({2, -1, -1, 0}));  // as given
  // [2 -1 -1 0] -> [3 0 0] (a1); [1 0 -1 0] -> [2 1 0]; [0 1 -1 0] -> [1 2 0]; [1 1 -2 3] -> [3 3 3].
  EXPECT_EQ(hcp.as<CrystalCompressionExperiment>().params.axis, (Indices{3, 0, 0}));
  for (const auto& [four, three] : std::vector<std::pair<std::string, Indices>>{
           {"[1, 0, -1, 0]", {2, 1, 0}}, {"[0, 1, -1, 0]", {1, 2, 0}}, {"[1, 1, -2, 3]", {3, 3, 3}}}) {
    const Spec s = parse_spec_text(R"({"experiment": "crystal_compression", "crystal": {"lattice": "hcp"}, "loading": {"axis": )" +
                                   four + "}}");
    EXPECT_EQ(s.as<CrystalCompressionExperiment>().params.axis, three) << four;
  }
  const Spec bcc = parse_spec_text(
      R"({"experiment": "crystal_confinement", "crystal": {"lattice": "bcc"}, "loading": {"axis": [1, 1, 1], "lateral": [1, -1, 0]}})");
  EXPECT_EQ(bcc.normalized.at("grain").at("shape"), "truncated_octahedron");
  EXPECT_EQ(bcc.as<CrystalConfinementExperiment>().params.lateral, (Indices{1, -1, 0}));
}

// Whole numbers are written as integers (issue 51): a direction reads [2, -1, -1, 0], not [2.0, -1.0, -1.0, 0.0],
// counts are integers, and the normalised spec read again is the same text (its hash, the reuse key, too).
TEST(SpecDefaults, WholeNumbersAreWrittenAsIntegers) {
  const Spec hcp = parse_spec_text(R"({"experiment": "crystal_shear", "crystal": {"lattice": "hcp"}})");
  const std::string text = hcp.normalized.dump();
  EXPECT_NE(text.find(R"("direction":[2,-1,-1,0])"), std::string::npos) << text;
  EXPECT_NE(text.find(R"("plane":[0,0,0,1])"), std::string::npos) << text;
  EXPECT_TRUE(hcp.normalized.at("crystal").at("grains_x").is_number_integer());
  const Spec given = parse_spec_text(
      R"({"experiment": "crystal_compression", "crystal": {"lattice": "sc"}, "loading": {"axis": [0.0, 1.0, 1]},
          "output": {"snapshot_strains": [0, 0.01]}})");
  EXPECT_EQ(given.normalized.at("loading").at("axis").dump(), "[0,1,1]");
  EXPECT_EQ(given.normalized.at("output").at("snapshot_strains").dump(), "[0.0,0.01]");  // not all whole: as numbers
  for (const Spec* s : {&hcp, &given}) {
    const Spec again = parse_spec_text(s->normalized.dump());
    EXPECT_EQ(again.normalized.dump(), s->normalized.dump());
    EXPECT_EQ(spec_hash(again.normalized), spec_hash(s->normalized));
  }
}

TEST(SpecDefaults, ShearPlaneAndDirectionAreTheSampleAxes) {
  const Spec fcc = parse_spec_text(R"({"experiment": "crystal_shear"})");
  EXPECT_EQ(fcc.normalized.at("loading").at("plane"), json({1.0, 1.0, 1.0}));
  EXPECT_EQ(fcc.normalized.at("loading").at("normal_stress"), fcc.normalized.at("loading").at("confining_pressure"));
  EXPECT_EQ(fcc.as<CrystalShearExperiment>().params.axis, (Indices{1, 1, 1}));
  EXPECT_EQ(fcc.as<CrystalShearExperiment>().params.lateral, (Indices{1, -1, 0}));
  // HCP's prism plane (1 0 -1 0): its normal is [2 1 0] of a1, a2; the basal direction c lies in it.
  const Spec hcp = parse_spec_text(
      R"({"experiment": "crystal_shear", "crystal": {"lattice": "hcp"}, "loading": {"plane": [1, 0, -1, 0], "direction": [0, 0, 0, 1]}})");
  EXPECT_EQ(hcp.as<CrystalShearExperiment>().params.axis, (Indices{2, 1, 0}));
  EXPECT_EQ(hcp.as<CrystalShearExperiment>().params.plane, (Indices{1, 0, 0}));
  EXPECT_EQ(hcp.as<CrystalShearExperiment>().params.lateral, (Indices{0, 0, 1}));
  // The dry run's estimate for the default: FCC (1 1 1) along [1 -1 0], between the two <112> senses.
  const auto e = fcc.experiment->yield_estimate();
  ASSERT_TRUE(e && e->found);
  EXPECT_GT(e->shear_over_normal, 0.884);
  EXPECT_LT(e->shear_over_normal, 1.405);
}

TEST(SpecDefaults, CrystalRateFollowsP0OverE) {
  const auto rate = [](const char* text) {
    return parse_spec_text(text).normalized["loading"]["rate_number"].get<double>();
  };
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"confining_pressure": 10000}})"),
                   1.5 * 1e4 / 3e9);
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"confining_pressure": 30000},
                            "material": {"youngs_modulus": 1e9}})"),
                   4.5e-5);
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"rate_number": 1e-4}})"), 1e-4);
  // A program, releasing the platen or not, runs at the same 1.5 p0 / E (its turns slow down: Fig. 1c's cycles
  // within 1.01 % of R = 5e-6 there).
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02,
                            "program": [{"to_strain": 0.01}, {"to_deviator": 0}, {"to_strain": 0.02}]}})"),
                   1.5 * 6e4 / 3e9);
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02,
                            "program": [{"to_strain": 0.02}, {"to_strain": 0.01}]}})"),
                   1.5 * 6e4 / 3e9);
  EXPECT_DOUBLE_EQ(rate(R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02,
                            "program": [{"to_strain": 0.01}, {"hold_steps": 100}, {"to_strain": 0.02}]}})"),
                   1.5 * 6e4 / 3e9);
}

TEST(SpecNormalized, TwoCubeContainsEveryDefault) {
  const json expected = {
      {"experiment", "two_cube_sliding"},
      {"label", ""},
      {"grain", {{"shape", "cube"}, {"size", 0.01}, {"edge_spheres", 10}, {"overlap", 0.75}}},
      {"material",
       {{"youngs_modulus", 3.0e9},
        {"density", 1200.0},
        {"friction", 0.3},
        {"tangential_stiffness_ratio", 2.0 / 7},
        {"damping", 0.05}}},
      {"contact", kDefaultContact},
      {"loading", {{"prestrain", 0.005}, {"max_slide", 0.8}, {"rate_number", 1e-5}}},
      {"output", {{"curve_points", 400}}},
      {"run", {{"threads", 0}, {"time_step_factor", 0.2}, {"skin_factor", 0.1}, {"kernel", "auto"}}},
  };
  EXPECT_EQ(parse_spec_text("{}").normalized, expected) << parse_spec_text("{}").normalized.dump(2);
}

TEST(SpecNormalized, IntegersStayIntegers) {
  const json n = parse_spec_text(R"({"grain": {"edge_spheres": 12.0}})").normalized;
  EXPECT_TRUE(n.at("grain").at("edge_spheres").is_number_integer());
  EXPECT_TRUE(n.at("output").at("curve_points").is_number_integer());
  EXPECT_TRUE(n.at("run").at("threads").is_number_integer());
}

TEST(SpecNormalized, RoundTripIsAFixedPoint) {
  for (const char* text : {"{}", R"({"experiment": "two_cube_sliding"})",
                           R"({"label": "x", "grain": {"edge_spheres": 6, "overlap": 0.6},
                               "material": {"friction": 0.123456789}, "run": {"threads": 2}})",
                           R"({"experiment": "crystal_compression"})", kContractCrystalExample}) {
    SCOPED_TRACE(text);
    const Spec first = parse_spec_text(text);
    // Through the JSON value and through its text (what is stored and hashed).
    const Spec again = parse_spec(first.normalized);
    EXPECT_EQ(again.normalized, first.normalized);
    const Spec from_text = parse_spec_text(first.normalized.dump());
    EXPECT_EQ(from_text.normalized, first.normalized);
    EXPECT_EQ(from_text.normalized.dump(), first.normalized.dump());
    EXPECT_STREQ(again.name(), first.name());
    EXPECT_EQ(again.label, first.label);
    EXPECT_EQ(again.threads, first.threads);
    if (std::string(first.name()) == "two_cube_sliding") {
      EXPECT_EQ(again.as<TwoCubeSlidingExperiment>().params.grain.edge_spheres,
                first.as<TwoCubeSlidingExperiment>().params.grain.edge_spheres);
      EXPECT_EQ(again.as<TwoCubeSlidingExperiment>().params.material.friction,
                first.as<TwoCubeSlidingExperiment>().params.material.friction);
    } else {
      EXPECT_EQ(again.as<CrystalCompressionExperiment>().params.rows_z,
                first.as<CrystalCompressionExperiment>().params.rows_z);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Errors name the field

struct ErrorCase {
  const char* name;  ///< gtest name suffix
  std::string text;  ///< the spec text given to parse_spec_text
  std::string code;
  std::string field;
  std::string mention = "";  ///< extra text what() must hold (the allowed range or choices)
};

std::ostream& operator<<(std::ostream& os, const ErrorCase& c) { return os << c.name << ": " << c.text; }

const std::vector<ErrorCase> kErrorCases = {
    // Unknown keys.
    {"UnknownTopLevelKey", R"({"experimnet": "two_cube_sliding"})", "unknown_field", "experimnet"},
    {"UnknownNestedKey", R"({"grain": {"edge_sphere": 10}})", "unknown_field", "grain.edge_sphere"},
    {"UnknownMaterialKey", R"({"material": {"poisson": 0.3}})", "unknown_field", "material.poisson"},
    {"UnknownRunKey", R"({"run": {"thread": 4}})", "unknown_field", "run.thread"},
    {"UnknownKeyWithNullValue", R"({"grain": {"edge_sphere": null}})", "unknown_field", "grain.edge_sphere"},
    {"CrystalSectionInTwoCube", R"({"experiment": "two_cube_sliding", "crystal": {"grains_x": 8}})", "unknown_field",
     "crystal"},
    {"CrystalSectionInDefaultExperiment", R"({"crystal": {}})", "unknown_field", "crystal"},
    {"CrystalLoadingInTwoCube", R"({"loading": {"max_strain": 0.1}})", "unknown_field", "loading.max_strain"},
    {"SnapshotsInTwoCube", R"({"output": {"snapshot_strains": [0.0]}})", "unknown_field", "output.snapshot_strains"},
    {"TwoCubeLoadingInCrystal", R"({"experiment": "crystal_compression", "loading": {"prestrain": 0.005}})",
     "unknown_field", "loading.prestrain"},
    {"UnknownCrystalKey", R"({"experiment": "crystal_compression", "crystal": {"grain_x": 8}})", "unknown_field",
     "crystal.grain_x"},

    // Wrong types.
    {"StringForNumber", R"({"grain": {"size": "0.01"}})", "wrong_type", "grain.size", "(0, 1]"},
    {"StringForInteger", R"({"grain": {"edge_spheres": "10"}})", "wrong_type", "grain.edge_spheres", "[2, 40]"},
    {"FloatForInteger", R"({"grain": {"edge_spheres": 10.5}})", "wrong_type", "grain.edge_spheres", "[2, 40]"},
    {"ObjectForNumber", R"({"material": {"friction": {"value": 0.3}}})", "wrong_type", "material.friction"},
    {"BoolForNumber", R"({"loading": {"prestrain": true}})", "wrong_type", "loading.prestrain"},
    {"ArrayForNumber", R"({"output": {"curve_points": [400]}})", "wrong_type", "output.curve_points"},
    {"ArrayForObjectSection", R"({"grain": [10, 0.75]})", "wrong_type", "grain"},
    {"StringForObjectSection", R"({"material": "steel"})", "wrong_type", "material"},
    {"NumberForExperiment", R"({"experiment": 1})", "wrong_type", "experiment"},
    {"NumberForLabel", R"({"label": 7})", "wrong_type", "label"},
    {"NumberForShape", R"({"grain": {"shape": 6}})", "wrong_type", "grain.shape"},
    {"NumberForKnockout", R"({"experiment": "crystal_compression", "crystal": {"knockout": 3}})", "wrong_type",
     "crystal.knockout"},
    {"StringInKnockout", R"({"experiment": "crystal_compression", "crystal": {"knockout": ["a"]}})", "wrong_type",
     "crystal.knockout"},

    // Out of range.
    {"EdgeSpheresTooFew", R"({"grain": {"edge_spheres": 1}})", "out_of_range", "grain.edge_spheres", "[2, 40]"},
    {"EdgeSpheresTooMany", R"({"grain": {"edge_spheres": 41}})", "out_of_range", "grain.edge_spheres", "[2, 40]"},
    {"EdgeSpheresNegative", R"({"grain": {"edge_spheres": -3}})", "out_of_range", "grain.edge_spheres", "[2, 40]"},
    {"OverlapOne", R"({"grain": {"overlap": 1.0}})", "out_of_range", "grain.overlap", "[0, 0.95]"},
    {"SizeZero", R"({"grain": {"size": 0}})", "out_of_range", "grain.size", "(0, 1]"},
    {"FrictionNegative", R"({"material": {"friction": -0.1}})", "out_of_range", "material.friction", "[0, 10]"},
    {"YoungsModulusZero", R"({"material": {"youngs_modulus": 0}})", "out_of_range", "material.youngs_modulus",
     "(0, 1e+13]"},
    {"PrestrainZero", R"({"loading": {"prestrain": 0}})", "out_of_range", "loading.prestrain", "(0, 0.1]"},
    {"MaxSlideTooLarge", R"({"loading": {"max_slide": 2}})", "out_of_range", "loading.max_slide", "(0, 1.5]"},
    {"CurvePointsZero", R"({"output": {"curve_points": 0}})", "out_of_range", "output.curve_points", "[1, 100000]"},
    {"ThreadsNegative", R"({"run": {"threads": -1}})", "out_of_range", "run.threads", "[0, 256]"},
    {"LabelTooLong", R"({"label": ")" + std::string(201, 'x') + R"("})", "out_of_range", "label", "200"},
    {"WallFrictionNegative", R"({"experiment": "crystal_compression", "loading": {"wall_friction": -0.1}})",
     "out_of_range", "loading.wall_friction", "[0, 10]"},
    {"KnockoutNegative", R"({"experiment": "crystal_compression", "crystal": {"knockout": [-1]}})", "out_of_range",
     "crystal.knockout", "[0, 863]"},
    {"SnapshotStrainTooLarge", R"({"experiment": "crystal_compression", "output": {"snapshot_strains": [0.0, 0.9]}})",
     "out_of_range", "output.snapshot_strains", "[0, 0.1]"},
    {"SnapshotBeyondMaxStrain",
     R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02}, "output": {"snapshot_strains": [0.04]}})",
     "out_of_range", "output.snapshot_strains", "[0, 0.02]"},
    {"PrestrainTooLarge", R"({"experiment": "crystal_compression", "material": {"youngs_modulus": 1e6}})",
     "out_of_range", "loading.confining_pressure", "0.02"},
    // Loading programs: a segment is named by its index.
    {"ProgramSegmentBeyondMaxStrain",
     R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02, "program": [{"to_strain": 0.01}, {"to_strain": 0.03}]}})",
     "out_of_range", "loading.program[1].to_strain", "[0, 0.02]"},
    {"ProgramSegmentEmpty",
     R"({"experiment": "crystal_compression", "loading": {"program": [{"to_strain": 0.01}, {"to_deviator": 0}, {}]}})",
     "out_of_range", "loading.program[2]", "exactly one of to_strain, to_deviator, hold_steps"},
    {"ProgramSegmentTwoKinds",
     R"({"experiment": "crystal_compression", "loading": {"program": [{"to_strain": 0.01, "hold_steps": 10}]}})",
     "out_of_range", "loading.program[0]", "exactly one of"},
    {"ProgramDeviatorBelowMinusP0",
     R"({"experiment": "crystal_compression", "loading": {"confining_pressure": 30000, "program": [{"to_strain": 0.01}, {"to_deviator": -30000}]}})",
     "out_of_range", "loading.program[1].to_deviator", "above -p0"},
    {"ProgramHoldZeroSteps", R"({"experiment": "crystal_compression", "loading": {"program": [{"hold_steps": 0}]}})",
     "out_of_range", "loading.program[0].hold_steps", "[1, 100000000]"},
    {"ProgramSegmentUnknownKey",
     R"({"experiment": "crystal_compression", "loading": {"program": [{"to_strain": 0.01}, {"to_stress": 1}]}})",
     "unknown_field", "loading.program[1].to_stress"},
    {"ProgramNotAList", R"({"experiment": "crystal_compression", "loading": {"program": {"to_strain": 0.01}}})",
     "wrong_type", "loading.program"},
    {"ConfinementUnknown", R"({"experiment": "crystal_compression", "loading": {"confinement": "latex"}})",
     "invalid_value", "loading.confinement", "fixed_forces"},
    {"CrystalTooLarge",
     R"({"experiment": "crystal_compression", "crystal": {"grains_x": 100, "rows_z": 400, "layers_y": 100}})",
     "out_of_range", "crystal", "50,000,000"},

    // Invalid choices.
    {"RhombicDodecahedronInTwoCube", R"({"grain": {"shape": "rhombic_dodecahedron"}})", "invalid_value", "grain.shape",
     "cube"},
    {"UnknownShapeInCrystal", R"({"experiment": "crystal_compression", "grain": {"shape": "sphere"}})", "invalid_value",
     "grain.shape", "rhombic_dodecahedron"},
    {"UnknownExperiment", R"({"experiment": "triaxial"})", "invalid_value", "experiment", "crystal_compression"},
    {"UnknownLattice", R"({"experiment": "crystal_compression", "crystal": {"lattice": "diamond"}})", "invalid_value",
     "crystal.lattice", "hcp"},
    {"GrainOfAnotherLattice",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "sc"}, "grain": {"shape": "rhombic_dodecahedron"}})",
     "out_of_range", "grain.shape", "cube"},

    // Loading axes.
    {"AxisOfTwoIndices", R"({"experiment": "crystal_compression", "loading": {"axis": [1, 1]}})", "out_of_range",
     "loading.axis", "three integers"},
    {"AxisNotIntegers", R"({"experiment": "crystal_compression", "loading": {"axis": [1, 0.5, 0]}})", "out_of_range",
     "loading.axis", "integers"},
    {"AxisZero", R"({"experiment": "crystal_compression", "loading": {"axis": [0, 0, 0]}})", "out_of_range",
     "loading.axis", "[0, 0, 0]"},
    {"FourIndicesOutsideHcp", R"({"experiment": "crystal_compression", "loading": {"axis": [2, -1, -1, 0]}})",
     "out_of_range", "loading.axis", "three integers"},
    {"FourIndicesNotSummingToZero",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "hcp"}, "loading": {"axis": [1, 1, 1, 0]}})",
     "out_of_range", "loading.axis", "U + V + T = 0"},
    {"LateralAlongTheAxis",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "sc"}, "loading": {"axis": [0, 0, 1], "lateral": [1, 0, 1]}})",
     "out_of_range", "loading.lateral", "normal"},
    {"HighIndexAxisOfALongThinBox",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "sc", "grains_x": 1, "layers_y": 1, "rows_z": 400}, "loading": {"axis": [12, 11, 10]}})",
     "out_of_range", "loading.axis", "lattice points"},
    {"HcpAxisWithNoShortNormal",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "hcp"}, "loading": {"axis": [5, 9, 11]}})",
     "out_of_range", "loading.axis", "no normal lattice direction"},
    // Shear planes and directions.
    {"ShearDirectionOutOfThePlane",
     R"({"experiment": "crystal_shear", "loading": {"plane": [1, 1, 1], "direction": [1, 0, 0]}})", "out_of_range",
     "loading.direction", "lie in"},
    {"ShearPlaneZero", R"({"experiment": "crystal_shear", "loading": {"plane": [0, 0, 0]}})", "out_of_range",
     "loading.plane", "(0, 0, 0)"},
    {"ShearPlaneFourIndicesWrongI",
     R"({"experiment": "crystal_shear", "crystal": {"lattice": "hcp"}, "loading": {"plane": [1, 0, 0, 0], "direction": [0, 0, 0, 1]}})",
     "out_of_range", "loading.plane", "i = -(h + k)"},
    {"ShearSlabTooThin",
     R"({"experiment": "crystal_shear", "crystal": {"lattice": "sc", "rows_z": 2}})", "out_of_range",
     "crystal.rows_z", "three or more"},
    {"ShearProgramBeyondTheLargestStrain",
     R"({"experiment": "crystal_shear", "loading": {"max_shear_strain": 0.1, "program": [{"to_shear_strain": -0.2}]}})",
     "out_of_range", "loading.program[0].to_shear_strain", ""},
    // Interface laws.
    {"UnknownNormalLaw", R"({"contact": {"normal": "mohr"}})", "invalid_value", "contact.normal", "hertz/material"},
    {"UnknownTangentialLaw", R"({"contact": {"tangential": "mindlin_rescale"}})", "invalid_value", "contact.tangential",
     "linear_history"},
    {"CohesiveLawWithoutSurfaceEnergy", R"({"experiment": "crystal_compression", "contact": {"normal": "jkr"}})",
     "out_of_range", "contact.surface_energy", "hertz/material"},
    {"StiffnessOfAnotherLaw", R"({"experiment": "crystal_stiffness", "contact": {"normal": "hertz/material"}})",
     "out_of_range", "contact.normal", "face-spring"},
    {"TruncatedOctahedronTooCoarse",
     R"({"experiment": "crystal_compression", "crystal": {"lattice": "bcc"}, "grain": {"edge_spheres": 2}})",
     "out_of_range", "grain.edge_spheres", "truncated_octahedron"},

    // The document itself.
    {"ArrayDocument", R"([{"experiment": "two_cube_sliding"}])", "wrong_type", ""},
    {"NumberDocument", "42", "wrong_type", ""},
    {"StringDocument", R"("two_cube_sliding")", "wrong_type", ""},
    {"NullDocument", "null", "wrong_type", ""},
    {"InvalidJson", R"({"experiment": "two_cube_sliding",})", "invalid_json", ""},
    {"TruncatedJson", R"({"grain": {"size": 0.01})", "invalid_json", ""},
    {"EmptyText", "", "invalid_json", ""},
    {"NanLiteral", R"({"grain": {"size": NaN}})", "invalid_json", ""},
    // 1e400 overflows a double: the parser stops there, and the error names the field it was given for.
    {"HugeNumber", R"({"grain": {"size": 1e400}})", "out_of_range", "grain.size", "too large"},
    {"HugeNegativeNumber", R"({"material": {"friction": -1e400}})", "out_of_range", "material.friction"},
    {"HugeNumberInAList", R"({"experiment": "crystal_compression", "output": {"snapshot_strains": [0, 1e999]}})",
     "out_of_range", "output.snapshot_strains[1]"},
    // Nesting is bounded while parsing (the limit is 64 levels).
    {"TooDeep", std::string(65, '[') + std::string(65, ']'), "too_deep",
     "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]["
     "0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]",
     "64"},
    {"TooDeepInALabel", R"({"label": )" + std::string(100, '[') + "1" + std::string(100, ']') + "}", "too_deep",
     "label[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
     "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"},
    {"InvalidUtf8InALabel", "{\"label\": \"caf\xe9\"}", "invalid_json", ""},
};

class SpecErrorTest : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(SpecErrorTest, NamesTheField) {
  const ErrorCase& c = GetParam();
  try {
    parse_spec_text(c.text);
    FAIL() << "no SpecError for " << c.text;
  } catch (const SpecError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.code, c.code) << what;
    EXPECT_EQ(e.field, c.field) << what;
    if (!c.field.empty()) {
      EXPECT_NE(what.find("'" + c.field + "'"), std::string::npos) << what;
    }
    if (!c.mention.empty()) {
      EXPECT_NE(what.find(c.mention), std::string::npos) << what;
    }
  } catch (const std::exception& e) {
    FAIL() << "expected a SpecError, got another exception: " << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Table, SpecErrorTest, ::testing::ValuesIn(kErrorCases),
                         [](const ::testing::TestParamInfo<ErrorCase>& info) { return std::string(info.param.name); });

TEST(SpecErrors, NonFiniteNumberFromCodeIsOutOfRange) {
  // JSON text cannot hold NaN or infinity, but a document built in C++ can.
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    json doc = {{"grain", {{"size", bad}}}};
    try {
      parse_spec(doc);
      FAIL() << "no SpecError for " << bad;
    } catch (const SpecError& e) {
      EXPECT_EQ(e.code, "out_of_range");
      EXPECT_EQ(e.field, "grain.size");
    }
  }
}

TEST(SpecErrors, AHugelyNestedDocumentIsRefusedAtTheLimitNotParsed) {
  // 150,000 levels (300 KB) crashed a recursive parser; this one stops at level 65.
  const std::string deep = std::string(150000, '[') + std::string(150000, ']');
  try {
    parse_spec_text(deep);
    FAIL() << "accepted";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.code, "too_deep");
  }
  // 64 levels are fine as JSON (the spec then rejects an array document, naming no field).
  try {
    parse_spec_text(std::string(64, '[') + std::string(64, ']'));
    FAIL() << "accepted";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.code, "wrong_type");
  }
}

TEST(SpecErrors, InvalidUtf8GivesAMessageThatIsValidJson) {
  try {
    parse_spec_text("{\"label\": \"\xff\xfe\"}");
    FAIL() << "accepted";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.code, "invalid_json");
    EXPECT_NE(std::string(e.what()).find("UTF-8"), std::string::npos) << e.what();
    EXPECT_NO_THROW(json({{"message", e.what()}}).dump());  // the server can answer with it
  }
}

TEST(SpecErrors, ErrorsAreRuntimeErrors) {
  // Callers that only catch std::runtime_error still see a spec error.
  EXPECT_THROW(parse_spec_text(R"({"grain": {"edge_spheres": 1}})"), std::runtime_error);
  EXPECT_THROW(parse_spec(json::array()), SpecError);
}

// ---------------------------------------------------------------------------------------------
// 4. Result formats

std::vector<TwoCubeRow> handmade_curve() {
  return {{0.0, 1.0, 0.3, 1500.0, 450.0}, {0.1, 0.9, 0.27, 1350.0, 405.0}, {0.2, 0.8, 0.24, 1200.0, 360.0}};
}

RunStats handmade_stats() {
  RunStats r;
  r.grains = 2;
  r.sphere_diameter = 0.001;
  r.normal_stiffness = 3.0e5;
  r.time_step = 1e-7;
  r.spheres_per_face = 100;
  r.spheres = 1000;
  r.steps = 20000;
  r.rebuilds = 12;
  r.wall_seconds = 4.0;
  r.threads = 2;
  return r;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string two_cube_csv(const std::vector<TwoCubeRow>& curve) {
  std::string csv = curve_csv_header(TwoCubeRow::columns());
  for (const TwoCubeRow& row : curve) csv += curve_csv_line(TwoCubeRow::columns(), row.values());
  return csv;
}

TEST(Results, CurveCsvHeaderAndOneLinePerRow) {
  const std::vector<TwoCubeRow> curve = handmade_curve();
  const std::string csv = two_cube_csv(curve);
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(csv.back(), '\n');
  const std::vector<std::string> lines = lines_of(csv);
  ASSERT_EQ(lines.size(), curve.size() + 1);
  EXPECT_EQ(lines[0], "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force");
  EXPECT_EQ(lines[1], "0,1,0.3,1500,450");
  for (std::size_t i = 1; i < lines.size(); ++i) {
    SCOPED_TRACE(lines[i]);
    std::istringstream row(lines[i]);
    std::vector<double> values;
    for (std::string cell; std::getline(row, cell, ',');) values.push_back(std::stod(cell));
    ASSERT_EQ(values.size(), 5u);
    const TwoCubeRow& expected = curve[i - 1];
    EXPECT_DOUBLE_EQ(values[0], expected.slide_over_size);
    EXPECT_DOUBLE_EQ(values[1], expected.normal_over_p0);
    EXPECT_DOUBLE_EQ(values[2], expected.tangential_over_p0);
    EXPECT_DOUBLE_EQ(values[3], expected.normal_force);
    EXPECT_DOUBLE_EQ(values[4], expected.tangential_force);
  }
}

TEST(Results, CurveCsvOfEmptyCurveIsTheHeaderAlone) {
  EXPECT_EQ(two_cube_csv({}), "slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force\n");
}

TEST(Results, CrystalCountsAreIntegersAndTheEnergyRatioHasSixDigits) {
  CrystalRow row{0.001, 61234.5678912, 60000, 612.345678912, -1e-5, 2e-5, 59999.5, 1.23456789e-3, 193012, 12, 3, {}};
  row.energy = {1.234567890123e-3, -2.5e-4, 3e-5, 4.0000000001e-4, 5e-7, 6e-9, -1.23456789012e-8};
  EXPECT_EQ(curve_csv_line(CrystalRow::columns(), row.values()),
            "0.001,61234.5679,60000,612.345679,-1e-05,2e-05,59999.5,0.00123457,193012,12,3,"
            "0.00123456789,-0.00025,3e-05,0.0004,5e-07,6e-09,-1.23456789e-08\n");
}

TEST(Results, SummaryJsonHasTheContractKeysWithUnits) {
  JsonSummaryWriter w;
  write_run_stats(w, handmade_stats());
  const json s = w.document();
  for (const char* key : {"spheres", "grains", "steps", "time_step", "wall_seconds", "threads",
                          "sphere_steps_per_second", "sphere_diameter", "normal_stiffness", "spheres_per_face"}) {
    SCOPED_TRACE(key);
    ASSERT_TRUE(s.contains(key));
    EXPECT_TRUE(s.at(key).is_number());
  }
  EXPECT_EQ(s.at("spheres"), 1000);
  EXPECT_EQ(s.at("grains"), 2);
  EXPECT_EQ(s.at("steps"), 20000);
  EXPECT_DOUBLE_EQ(s.at("time_step").get<double>(), 1e-7);
  EXPECT_DOUBLE_EQ(s.at("wall_seconds").get<double>(), 4.0);
  EXPECT_EQ(s.at("threads"), 2);
  EXPECT_DOUBLE_EQ(s.at("sphere_steps_per_second").get<double>(), 1000.0 * 20000 / 4.0);
  EXPECT_DOUBLE_EQ(s.at("sphere_diameter").get<double>(), 0.001);
  EXPECT_DOUBLE_EQ(s.at("normal_stiffness").get<double>(), 3.0e5);
  EXPECT_EQ(s.at("spheres_per_face"), 100);
  // Units by dotted key, nested groups included.
  EXPECT_EQ(w.units().at("time_step"), "s");
  EXPECT_EQ(w.units().at("normal_stiffness"), "N/m");
  EXPECT_EQ(w.units().at("stage_seconds.contact_forces"), "s");
}

TEST(Results, SummaryJsonZeroWallTimeGivesZeroRate) {
  RunStats r = handmade_stats();
  r.wall_seconds = 0;
  JsonSummaryWriter w;
  write_run_stats(w, r);
  EXPECT_EQ(w.document().at("sphere_steps_per_second").get<double>(), 0.0);
  // No inf or NaN anywhere (nlohmann would write them as null, silently).
  std::function<void(const nlohmann::json&)> finite = [&](const nlohmann::json& j) {
    if (j.is_number_float()) {
      EXPECT_TRUE(std::isfinite(j.get<double>())) << j;
    }
    if (j.is_structured())
      for (const auto& v : j) finite(v);
  };
  finite(w.document());
}

TEST(Results, SummaryJsonListsAndGroups) {
  JsonSummaryWriter w;
  w.begin_group("peak");
  w.number("deviator", 5.0, "Pa");
  w.end_group();
  w.begin_list("snapshots");
  for (int k = 0; k < 2; ++k) {
    w.begin_group(nullptr);
    w.count("index", std::uint64_t(k));
    w.number("strain", 0.01 * k, "-");
    w.end_group();
  }
  w.end_list();
  w.begin_list("warnings");
  w.text(nullptr, "a sentence");
  w.end_list();
  EXPECT_EQ(w.document(), json::parse(R"({"peak": {"deviator": 5.0}, "snapshots": [{"index": 0, "strain": 0.0},
      {"index": 1, "strain": 0.01}], "warnings": ["a sentence"]})"));
  // Counts have a unit too ("-"): every number in a summary has one.
  EXPECT_EQ(w.units(), json::parse(R"({"peak.deviator": "Pa", "snapshots[].index": "-", "snapshots[].strain": "-"})"));
}

}  // namespace
}  // namespace granulab::api

namespace granulab::api {
namespace {

// Without explicit snapshot strains, the paper's list is cut at max_strain instead of failing.
TEST(SpecDefaults, DefaultSnapshotsStopAtMaxStrain) {
  const Spec spec = parse_spec_text(R"({"experiment": "crystal_compression", "loading": {"max_strain": 0.02}})");
  EXPECT_EQ(spec.as<CrystalCompressionExperiment>().params.snapshot_strains, (std::vector<double>{0.0, 0.01, 0.02}));
}

// The platens' friction follows the grains' unless given.
TEST(SpecDefaults, WallFrictionFollowsMaterialFriction) {
  EXPECT_EQ(parse_spec_text(R"({"experiment": "crystal_compression", "material": {"friction": 0.2}})")
                .as<CrystalCompressionExperiment>()
                .params.wall_friction,
            0.2);
  EXPECT_EQ(parse_spec_text(R"({"experiment": "crystal_compression", "loading": {"wall_friction": 1.5}})")
                .as<CrystalCompressionExperiment>()
                .params.wall_friction,
            1.5);
}

}  // namespace
}  // namespace granulab::api
