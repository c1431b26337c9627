#include "engine/crystal/sample_parameters.h"

#include <string>

#include "engine/model/model_parameters.h"

namespace granulab {

void visit_crystal_sample(ParameterVisitor& v, CrystalSampleParams& p) {
  visit_grain(v, p.grain);
  visit_material(v, p.material);
  p.skin_factor = crystal_skin_factor(p.grain.overlap);
  visit_integration(v, p.time_step_factor, p.skin_factor);

  v.section("crystal");
  v.integer("grains_x", p.grains_x, 1, 100, "grains per row (x)");
  v.integer("rows_z", p.rows_z, 1, 400, "rows along the compression axis (z)");
  v.integer("layers_y", p.layers_y, 1, 100, "{111} layers through the thickness (y)");
  const long last_id = long(p.grains_x) * p.rows_z * p.layers_y - 1;
  v.grain_ids("knockout", p.knockout_ids, std::uint32_t(last_id), "crystal.grains_x x rows_z x layers_y - 1", 100000,
              "grains removed, by id (layer-major, then row, then column)");
  const std::size_t regions = v.begin_list("knockout_regions", 1000, "cylinders removed through the thickness");
  p.knockout_regions.resize(regions);
  for (std::size_t i = 0; i < regions; ++i) {
    v.begin_item(i);
    KnockoutRegion& k = p.knockout_regions[i];
    v.number("x", k.x, {-1000, 1000}, "a", "centre offset along x from the sample centre, in grain sizes");
    v.number("z", k.z, {-1000, 1000}, "a", "centre offset along z from the sample centre, in grain sizes");
    k.radius = 1;
    v.number("radius", k.radius, {0, 1000, true}, "a", "radius, in grain sizes");
    v.end_item();
  }
  v.end_list();

  v.section("imperfections");
  ImperfectionParams& im = p.imperfections;
  v.number("size_dispersion", im.size_dispersion, {0, 0.05}, "-",
           "sigma_s: each grain's size is a (1 - sigma_s |z|), z standard normal: never larger than its lattice site "
           "(docs/model.md, \"Imperfect grains\")");
  v.number("misorientation", im.misorientation, {0, 5}, "deg",
           "sigma_r: each grain is turned about a random axis by an rms angle sigma_r, then shrunk to fit its site");
  int seed = int(im.seed);
  v.integer("seed", seed, 0, 2147483647, "the draw: the same seed gives the same grains");
  im.seed = std::uint64_t(seed);

  v.section("loading");
  v.number("confining_pressure", p.confining_pressure, {0, 1e8, true}, "Pa", "p0, the vacuum bag's pressure");
  v.number("mass_scaling", p.mass_scaling, {1, 1e8}, "-", "density factor");
  p.wall_friction = p.material.friction;
  v.number("wall_friction", p.wall_friction, {0, 10}, "-",
           "Coulomb coefficient between spheres and the two platens (default: material.friction)");

  // The pre-strain that carries p0 must stay a small elastic overlap.
  const double prestrain = hydrostatic_prestrain(p.confining_pressure, p.material.youngs_modulus);
  v.require(prestrain <= 0.02, "loading.confining_pressure",
            "'loading.confining_pressure' gives a pre-strain sqrt2 p0 / E = " + std::to_string(prestrain) +
                " > 0.02: lower it or raise 'material.youngs_modulus'");
  // Memory: about 60 bytes per sphere; 5e7 spheres is 3 GB.
  const double spheres = double(p.grains_x) * p.rows_z * p.layers_y * double(sphere_count(p.grain));
  v.require(spheres <= 5e7, "crystal",
            "'crystal' would hold " + std::to_string(long(spheres)) +
                " spheres (grains_x x rows_z x layers_y x spheres per grain); the limit is 50,000,000");
}

}  // namespace granulab
