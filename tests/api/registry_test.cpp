// The experiment registry is the one seam: every registered experiment reads its defaults, runs through
// the one runner and describes itself; an unknown name is refused, never run as another experiment; the
// names appear in product code only in the experiment's own folder and the registry; and docs/spec.md is
// what the registry says.
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "api/runner.h"
#include "api/spec.h"
#include "api/spec_docs.h"

namespace granulab::api {
namespace {

namespace fs = std::filesystem;
const fs::path kSource = GRANULAB_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Registry, NamesAreUniqueAndEachReadsItsDefaults) {
  std::set<std::string> names;
  for (const ExperimentType& t : experiment_types()) {
    SCOPED_TRACE(t.name);
    EXPECT_TRUE(names.insert(t.name).second);
    EXPECT_EQ(find_experiment_type(t.name), &t);
    const Spec spec = parse_spec(nlohmann::json{{"experiment", t.name}});
    EXPECT_EQ(spec.type, &t);
    EXPECT_EQ(spec.normalized.at("experiment"), t.name);
    EXPECT_FALSE(spec.experiment->curve_columns().empty());
    // The normalised spec is a fixed point.
    EXPECT_EQ(parse_spec(spec.normalized).normalized, spec.normalized);
  }
  EXPECT_EQ(find_experiment_type("triaxial"), nullptr);
}

TEST(Registry, AnUnknownExperimentIsRefusedWithTheRegisteredNames) {
  try {
    parse_spec(nlohmann::json{{"experiment", "triaxial"}});
    FAIL() << "an unknown experiment was accepted";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.field, "experiment");
    for (const ExperimentType& t : experiment_types()) EXPECT_NE(std::string(e.what()).find(t.name), std::string::npos);
  }
}

// Product code dispatches through the registry only: an experiment's name appears in its own folder and
// in registry.cpp, nowhere else under engine/, api/, server/ and clients/cli/.
TEST(Registry, ExperimentNamesAppearOnlyInTheirFolderAndTheRegistry) {
  for (const ExperimentType& t : experiment_types()) {
    const fs::path own = kSource / "engine" / "experiments" / t.name;
    EXPECT_TRUE(fs::is_directory(own)) << own;
    for (const char* root : {"engine", "api", "server", "clients/cli"})
      for (const auto& entry : fs::recursive_directory_iterator(kSource / root)) {
        const fs::path p = entry.path();
        if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h")) continue;
        if (p.filename() == "registry.cpp" || p.string().rfind(own.string() + "/", 0) == 0) continue;
        EXPECT_EQ(read(p).find(t.name), std::string::npos) << p << " names " << t.name;
      }
  }
}

// The second seam closed: outside the engine nothing recognises an experiment by its curve columns or
// the summary values its headline names (the pictures, the CLI, the sweep routes and the web page read the
// headline instead). Searched in the api, the server, its page and the CLI as quoted names ("deviator",
// 'deviator') and, in the page's script, as members (x.deviator). A snapshot's "strain" and "step" are
// another thing's words, and so is a slip band's "dilation_angle" (every crystal snapshot's, slip_bands.h).
TEST(Registry, CurveColumnsAndHeadlineValuesAppearOnlyInTheirExperimentsFolder) {
  const std::set<std::string> shared = {"strain", "step", "dilation_angle"};
  std::size_t searched = 0;
  for (const ExperimentType& t : experiment_types()) {
    const std::unique_ptr<Experiment> e = t.make();
    std::set<std::string> names;
    for (const CurveColumn& c : e->curve_columns()) names.insert(c.name);
    for (const KeyValue& v : e->headline().values)
      names.insert(std::string(v.key).substr(0, std::string(v.key).find('.')));
    for (const SummaryTable& table : e->headline().tables) names.insert(table.key);
    for (const char* root : {"api", "server", "clients/cli"})
      for (const auto& entry : fs::recursive_directory_iterator(kSource / root)) {
        const fs::path p = entry.path();
        const bool script = p.extension() == ".js";
        if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h" && !script)) continue;
        const std::string text = read(p);
        ++searched;
        for (const std::string& name : names) {
          if (shared.count(name)) continue;
          for (const std::string& quoted : {"\"" + name + "\"", "'" + name + "'"})
            EXPECT_EQ(text.find(quoted), std::string::npos) << p << " names " << t.name << "'s " << quoted;
          if (!script) continue;
          for (const char after : {' ', ')', ',', ';', '.', '/', '*', '+', '-', '<', '>', '='}) {
            EXPECT_EQ(text.find("." + name + after), std::string::npos) << p << " names " << t.name << "'s ." << name;
          }
        }
      }
  }
  EXPECT_GT(searched, 60u);
}

// The one runner streams the same rows the summary counts, for every experiment (a short run of each).
TEST(Registry, EveryExperimentRunsThroughTheOneRunner) {
  const std::map<std::string, std::string> short_specs = {
      {"two_cube_sliding",
       R"({"grain": {"edge_spheres": 3}, "loading": {"rate_number": 1e-3}, "output": {"curve_points": 5}})"},
      {"crystal_compression", R"({"grain": {"edge_spheres": 3}, "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
        "loading": {"confining_pressure": 30e3, "max_strain": 1e-4}, "output": {"curve_points": 4, "snapshot_strains": [0]}})"},
      {"crystal_confinement", R"({"grain": {"edge_spheres": 3}, "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
        "loading": {"confining_pressure": 30e3}})"},
      {"crystal_shear", R"({"grain": {"edge_spheres": 3}, "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 3, "layers_y": 2},
        "loading": {"confining_pressure": 30e3, "max_shear_strain": 1e-4}, "output": {"curve_points": 4, "snapshot_strains": [0]}})"},
      {"crystal_stiffness", R"({"grain": {"edge_spheres": 3}, "crystal": {"lattice": "sc", "grains_x": 3, "rows_z": 3, "layers_y": 3},
        "loading": {"confining_pressure": 30e3, "ramp_transits": 1, "relax_checks": 1}})"},
      {"crystal_tension", R"({"grain": {"edge_spheres": 3}, "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 3, "layers_y": 2},
        "contact": {"normal": "dmt", "surface_energy": 1}, "loading": {"confining_pressure": 100, "max_strain": 1e-4},
        "output": {"curve_points": 4, "snapshot_strains": [0]}})"}};
  for (const ExperimentType& t : experiment_types()) {
    SCOPED_TRACE(t.name);
    ASSERT_TRUE(short_specs.count(t.name)) << "add a short spec for the new experiment here";
    nlohmann::json doc = nlohmann::json::parse(short_specs.at(t.name));
    doc["experiment"] = t.name;
    const RunOutput out = run_spec(parse_spec(doc));
    EXPECT_EQ(out.summary.at("experiment"), t.name);
    // The admission estimate (server budgets) against the run: the same size, no fewer steps than run.
    const Workload w = parse_spec(doc).experiment->workload();
    EXPECT_EQ(out.summary.at("spheres").get<double>(), w.spheres);
    EXPECT_LE(out.summary.at("steps").get<double>(), w.steps);
    if (out.summary.contains("compression_steps")) {  // the part not bounded by the confinement's cap
      EXPECT_LE(out.summary.at("compression_steps").get<double>(), w.steps - 200000);
    }
    std::printf("%s: %g spheres, %g steps run, %g estimated\n", t.name, w.spheres,
                out.summary.at("steps").get<double>(), w.steps);
    EXPECT_GT(out.summary.at("steps").get<double>(), 0);
    EXPECT_TRUE(out.summary.at("warnings").is_array());
    EXPECT_EQ(out.summary.at("units").at("time_step"), "s");
    // Rows were streamed: at least two, each with one value per column.
    const std::size_t columns = parse_spec(doc).experiment->curve_columns().size();
    std::size_t rows = 0;
    std::istringstream lines(out.curve_csv);
    std::string line;
    std::getline(lines, line);  // the header
    for (; std::getline(lines, line); ++rows)
      EXPECT_EQ(std::size_t(std::count(line.begin(), line.end(), ',')) + 1, columns) << line;
    EXPECT_GE(rows, 2u);
    const std::string header = out.curve_csv.substr(0, out.curve_csv.find('\n'));
    EXPECT_EQ(header + "\n", [&] {
      std::string h;
      for (const CurveColumn& c : parse_spec(doc).experiment->curve_columns())
        h += (h.empty() ? "" : ",") + std::string(c.name);
      return h + "\n";
    }());
  }
}

// docs/spec.md is generated from the registry: regenerate it with
//   build/granulab experiments --markdown > docs/spec.md
TEST(Registry, DocsSpecIsTheRegistrysOwnDescription) {
  const std::string markdown = experiments_markdown();
  for (const ExperimentType& t : experiment_types())
    EXPECT_NE(markdown.find(std::string("## `") + t.name + "`"), std::string::npos) << t.name;
  EXPECT_EQ(read(kSource / "docs" / "spec.md"), markdown)
      << "docs/spec.md is out of date: build/granulab experiments --markdown > docs/spec.md";
}

// Every field in the description has a unit column and a meaning, and the defaults are what a bare spec
// normalises to.
TEST(Registry, DescriptionsMatchTheNormalisedDefaults) {
  const nlohmann::json description = experiments_json();
  ASSERT_EQ(description["experiments"].size(), experiment_types().size());
  for (const nlohmann::json& e : description["experiments"]) {
    const Spec spec = parse_spec(nlohmann::json{{"experiment", e["name"]}});
    for (const nlohmann::json& f : e["fields"]) {
      const std::string field = f["field"];
      SCOPED_TRACE(field);
      EXPECT_FALSE(f["meaning"].get<std::string>().empty());
      if (field.find("[]") != std::string::npos) continue;  // list items: no default of their own
      const auto dot = field.find('.');
      const nlohmann::json& value = dot == std::string::npos
                                        ? spec.normalized.at(field)
                                        : spec.normalized.at(field.substr(0, dot)).at(field.substr(dot + 1));
      EXPECT_EQ(value, f["default"]);
    }
  }
}

}  // namespace
}  // namespace granulab::api
