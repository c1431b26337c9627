#include "api/spec.h"

#include <algorithm>
#include <cmath>

#include "api/object_reader.h"

namespace granulab::api {

namespace {

constexpr const char* kTwoCube = "two_cube_sliding";
constexpr const char* kCrystal = "crystal_compression";

GrainGeometry read_grain(ObjectReader& r, const GrainGeometry& def) {
  GrainGeometry g;
  // Each experiment has one grain shape: cubes slide in section 3, dodecahedra tile the crystal.
  r.choice("shape", to_string(def.shape), {to_string(def.shape).c_str()});
  g.shape = def.shape;
  g.size = r.number("size", def.size, 0, 1, true);
  g.edge_spheres = int(r.integer("edge_spheres", def.edge_spheres, 2, 40));
  g.overlap = r.number("overlap", def.overlap, 0, 0.95);
  return g;
}

Material read_material(ObjectReader& r, const Material& def) {
  Material m;
  m.youngs_modulus = r.number("youngs_modulus", def.youngs_modulus, 0, 1e13, true);
  m.density = r.number("density", def.density, 0, 1e5, true);
  m.friction = r.number("friction", def.friction, 0, 10);
  m.tangential_stiffness_ratio = r.number("tangential_stiffness_ratio", def.tangential_stiffness_ratio, 0, 1);
  m.damping = r.number("damping", def.damping, 0, 0.99);
  return m;
}

void read_crystal(const nlohmann::json& document, CrystalParams& c, ObjectReader& loading, ObjectReader& output,
                  nlohmann::json& out) {
  ObjectReader crystal(document, "crystal", "crystal");
  c.grains_x = int(crystal.integer("grains_x", c.grains_x, 1, 100));
  c.rows_z = int(crystal.integer("rows_z", c.rows_z, 1, 400));
  c.layers_y = int(crystal.integer("layers_y", c.layers_y, 1, 100));
  const long last_id = long(c.grains_x) * c.rows_z * c.layers_y - 1;
  for (long id : crystal.integers("knockout", 0, last_id, 100000)) c.knockout_ids.push_back(std::uint32_t(id));
  const std::vector<nlohmann::json> regions = crystal.objects("knockout_regions", 1000);
  nlohmann::json normalized_regions = nlohmann::json::array();
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const nlohmann::json holder = {{"region", regions[i]}};
    ObjectReader r(holder, "region", "crystal.knockout_regions[" + std::to_string(i) + "]");
    KnockoutRegion k;
    k.x = r.number("x", 0, -1000, 1000);
    k.z = r.number("z", 0, -1000, 1000);
    k.radius = r.number("radius", 1, 0, 1000, true);
    c.knockout_regions.push_back(k);
    normalized_regions.push_back(r.finish());
  }
  crystal.set_normalized("knockout_regions", normalized_regions);
  out["crystal"] = crystal.finish();

  c.confining_pressure = loading.number("confining_pressure", c.confining_pressure, 0, 1e8, true);
  c.max_strain = loading.number("max_strain", c.max_strain, 0, 0.5, true);
  c.rate_number = loading.number("rate_number", c.rate_number, 1e-8, 0.1);
  c.mass_scaling = loading.number("mass_scaling", c.mass_scaling, 1, 1e8);
  c.wall_friction = loading.number("wall_friction", c.material.friction, 0, 10);
  c.curve_points = int(output.integer("curve_points", c.curve_points, 1, 100000));
  // By default, the paper's snapshot strains that the run reaches; explicit ones must be reachable.
  std::vector<double> reachable;
  for (double e : c.snapshot_strains)
    if (e <= c.max_strain) reachable.push_back(e);
  c.snapshot_strains = output.numbers("snapshot_strains", reachable, 0, c.max_strain, 1000);

  // Cross-field limits. The pre-strain that carries p0 must stay a small elastic overlap.
  const double prestrain = std::sqrt(2.0) * c.confining_pressure / c.material.youngs_modulus;
  if (prestrain > 0.02)
    throw SpecError("out_of_range", "loading.confining_pressure",
                    "'loading.confining_pressure' gives a pre-strain sqrt2 p0 / E = " + std::to_string(prestrain) +
                        " > 0.02: lower it or raise 'material.youngs_modulus'");
  // Memory: about 60 bytes per sphere; 5e7 spheres is 3 GB.
  const double m = c.grain.edge_spheres - 2, per_grain = 12 * m * m + 24 * m + 14;
  const double spheres = double(c.grains_x) * c.rows_z * c.layers_y * per_grain;
  if (spheres > 5e7)
    throw SpecError("out_of_range", "crystal",
                    "'crystal' would hold " + std::to_string(long(spheres)) +
                        " spheres (grains_x x rows_z x layers_y x spheres per grain); the limit is 50,000,000");
}

}  // namespace

Spec parse_spec(const nlohmann::json& document) {
  ObjectReader top(document);
  Spec spec;
  const std::string experiment = top.choice("experiment", kTwoCube, {kTwoCube, kCrystal});
  spec.experiment = experiment == kTwoCube ? Experiment::two_cube_sliding : Experiment::crystal_compression;
  spec.label = top.text("label", "", 200);
  const bool cube = spec.experiment == Experiment::two_cube_sliding;
  for (const char* section : {"grain", "material", "loading", "output", "run"}) top.known(section);
  if (!cube) top.known("crystal");
  nlohmann::json out = top.finish();  // the sections are added below, normalised

  TwoCubeParams& tc = spec.two_cube;
  CrystalParams& cr = spec.crystal;
  ObjectReader grain(document, "grain", "grain");
  ObjectReader material(document, "material", "material");
  ObjectReader loading(document, "loading", "loading");
  ObjectReader output(document, "output", "output");
  ObjectReader run(document, "run", "run");
  spec.threads = int(run.integer("threads", 0, 0, 256));
  const double time_step_factor = run.number("time_step_factor", 0.2, 0, 0.5, true);
  // Crystals are dense and quasi-static: the default skin keeps only the touching (in-line) pairs as
  // candidates. The next sphere across a face sits at d sqrt(1 + (1 - kappa)^2) (1.031 d at kappa =
  // 0.75); a skin beyond that makes every contact drag its neighbours along (5x slower, measured). Once
  // faces slide, their sphere grids no longer line up and a sphere has ~ 2 pi d skin / s^2 candidates
  // across the face (3 at 0.03 d, 1 at 0.01 d), while the platen's motion triggers a rebuild every skin/2
  // of travel: 0.01 d balances the two (reference crystal: 0.0039 s/step to 5 % strain, 0.0068 at 0.03 d;
  // bench/README.md).
  const double kappa = grain.number("overlap", 0.75, 0, 0.95);  // read again, identically, below
  const double neighbour_gap = std::sqrt(1 + (1 - kappa) * (1 - kappa)) - 1;
  const double skin_factor = run.number("skin_factor", cube ? 0.1 : std::min(0.01, 0.9 * neighbour_gap), 0, 1, true);

  if (cube) {
    tc.grain = read_grain(grain, tc.grain);
    tc.material = read_material(material, tc.material);
    tc.time_step_factor = time_step_factor;
    tc.skin_factor = skin_factor;
    tc.prestrain = loading.number("prestrain", tc.prestrain, 0, 0.1, true);
    tc.max_slide = loading.number("max_slide", tc.max_slide, 0, 1.5, true);
    tc.rate_number = loading.number("rate_number", tc.rate_number, 1e-8, 0.1);
    tc.curve_points = int(output.integer("curve_points", tc.curve_points, 1, 100000));
  } else {
    cr.grain = read_grain(grain, cr.grain);
    cr.material = read_material(material, cr.material);
    cr.time_step_factor = time_step_factor;
    cr.skin_factor = skin_factor;
    read_crystal(document, cr, loading, output, out);
  }
  out["grain"] = grain.finish();
  out["material"] = material.finish();
  out["loading"] = loading.finish();
  out["output"] = output.finish();
  out["run"] = run.finish();
  spec.normalized = out;
  return spec;
}

Spec parse_spec_text(const std::string& text) {
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range 406 for 1e400
    throw SpecError("invalid_json", "", std::string("the spec is not valid JSON: ") + e.what());
  }
  return parse_spec(document);
}

}  // namespace granulab::api
