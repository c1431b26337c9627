#include "api/spec.h"

#include "api/object_reader.h"

namespace granulab::api {

namespace {

constexpr const char* kTwoCube = "two_cube_sliding";
constexpr const char* kCrystal = "crystal_compression";

GrainGeometry read_grain(ObjectReader& r, const GrainGeometry& def, bool cube_only) {
  GrainGeometry g;
  const std::string shape = cube_only ? r.choice("shape", "cube", {"cube"})
                                      : r.choice("shape", to_string(def.shape), {"rhombic_dodecahedron", "cube"});
  g.shape = shape == "cube" ? Shape::cube : Shape::rhombic_dodecahedron;
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

  TwoCubeParams tc;  // the two-cube defaults; the crystal ones are the contract's example
  const GrainGeometry grain_default = cube ? tc.grain : GrainGeometry{Shape::rhombic_dodecahedron, 0.01, 10, 0.75};
  const Material material_default = cube ? tc.material : Material{};

  ObjectReader grain(document, "grain", "grain");
  tc.grain = read_grain(grain, grain_default, cube);
  ObjectReader material(document, "material", "material");
  tc.material = read_material(material, material_default);
  ObjectReader loading(document, "loading", "loading");
  ObjectReader output(document, "output", "output");
  ObjectReader run(document, "run", "run");
  spec.threads = int(run.integer("threads", 0, 0, 256));
  tc.time_step_factor = run.number("time_step_factor", tc.time_step_factor, 0, 0.5, true);
  tc.skin_factor = run.number("skin_factor", tc.skin_factor, 0, 1, true);

  if (cube) {
    tc.prestrain = loading.number("prestrain", tc.prestrain, 0, 0.1, true);
    tc.max_slide = loading.number("max_slide", tc.max_slide, 0, 1.5, true);
    tc.rate_number = loading.number("rate_number", tc.rate_number, 1e-8, 0.1);
    tc.curve_points = int(output.integer("curve_points", tc.curve_points, 1, 100000));
  } else {
    ObjectReader crystal(document, "crystal", "crystal");
    crystal.integer("grains_x", 8, 1, 100);
    crystal.integer("rows_z", 18, 1, 400);
    crystal.integer("layers_y", 6, 1, 100);
    crystal.numbers("knockout", {}, 0, 1e9, 100000);
    out["crystal"] = crystal.finish();
    loading.number("confining_pressure", 60e3, 0, 1e8);
    loading.number("max_strain", 0.1, 0, 0.5, true);
    loading.number("rate_number", 1e-4, 1e-8, 0.1);
    loading.number("mass_scaling", 1, 1, 1e8);
    output.integer("curve_points", 400, 1, 100000);
    output.numbers("snapshot_strains", {0.0, 0.01, 0.02, 0.04, 0.08}, 0, 0.5, 1000);
  }
  out["grain"] = grain.finish();
  out["material"] = material.finish();
  out["loading"] = loading.finish();
  out["output"] = output.finish();
  out["run"] = run.finish();
  spec.two_cube = tc;
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
