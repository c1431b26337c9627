#include "engine/crystal/sample_parameters.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/model/model_parameters.h"

namespace granulab {

namespace {

bool integral(double x) { return std::abs(x - std::round(x)) < 1e-9; }

// A lattice direction from the spec: three integers, or for HCP also the four-index [U, V, T, W] with
// U + V + T = 0 (u = U - T, v = V - T, w = W). Leaves `out` alone when the list is not one.
void read_direction(ParameterVisitor& v, const char* field, const std::vector<double>& in, LatticeType lattice,
                    Indices& out) {
  const bool four = lattice == LatticeType::hcp && in.size() == 4;
  const bool sized = in.size() == 3 || four;
  v.require(sized, field,
            std::string("'") + field + "' must hold three integers [u, v, w]" +
                (lattice == LatticeType::hcp ? " or four [U, V, T, W]" : ""));
  if (!sized) return;
  const bool whole = std::all_of(in.begin(), in.end(), integral);
  v.require(whole, field, std::string("'") + field + "' must hold integers (lattice indices)");
  if (!whole) return;
  if (four) {
    const long u = std::lround(in[0]), w = std::lround(in[1]), t = std::lround(in[2]);
    v.require(u + w + t == 0, field, std::string("'") + field + "' in four indices [U, V, T, W] needs U + V + T = 0");
    out = Indices{int(u - t), int(w - t), int(std::lround(in[3]))};
  } else {
    out = Indices{int(std::lround(in[0])), int(std::lround(in[1])), int(std::lround(in[2]))};
  }
}

std::vector<double> as_numbers(const Indices& n) { return {double(n[0]), double(n[1]), double(n[2])}; }

}  // namespace

void visit_crystal_sample(ParameterVisitor& v, CrystalSampleParams& p) {
  v.section("crystal");
  std::string lattice = to_string(p.lattice);
  v.choice("lattice", lattice, {"fcc", "sc", "bcc", "hcp"},
           "the crystal, each grain the Voronoi cell of its site: fcc (rhombic dodecahedra, the paper's), sc (cubes), "
           "bcc (truncated octahedra), hcp (ideal c/a, trapezo-rhombic dodecahedra); the grain shape follows");
  lattice_from_string(lattice, p.lattice);
  p.grain.shape = grain_shape(p.lattice);
  visit_grain(v, p.grain,
              {Shape::rhombic_dodecahedron, Shape::cube, Shape::truncated_octahedron, Shape::trapezo_rhombic_dodecahedron},
              "a " + lattice + " crystal's grains are ");
  visit_material(v, p.material);
  p.skin_factor = crystal_skin_factor(p.grain.overlap);
  visit_integration(v, p.time_step_factor, p.skin_factor);

  v.section("crystal");
  v.integer("grains_x", p.grains_x, 1, 100, "grains per row (x): the box is grains_x lattice repeats along x");
  v.integer("rows_z", p.rows_z, 1, 400,
            "rows along the compression axis (z): the box holds about grains_x x layers_y x rows_z grains");
  v.integer("layers_y", p.layers_y, 1, 100, "layers through the thickness (y): {111} for the paper's crystal");
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
  p.axis = default_axis(p.lattice);
  std::vector<double> axis = as_numbers(p.axis);
  v.numbers("axis", axis, {-12, 12}, 4, "-",
            "the compression axis (lab z) as a lattice direction [u, v, w]: cubic indices for sc, fcc and bcc; for hcp "
            "along a1, a2, c, or the four-index [U, V, T, W] (default: [-1, -1, 2] for fcc, the paper's off-axis "
            "crystal; [0, 0, 1] for the others)");
  read_direction(v, "loading.axis", axis, p.lattice, p.axis);
  v.require(p.axis != Indices{0, 0, 0}, "loading.axis", "'loading.axis' must not be [0, 0, 0]");
  std::vector<double> lateral;
  if (p.lateral != Indices{0, 0, 0}) lateral = as_numbers(p.lateral);
  v.numbers("lateral", lateral, {-12, 12}, 4, "-",
            "the sample's x axis, a lattice direction normal to loading.axis, in the same indices (default, []: the "
            "shortest lattice translation normal to the axis; [1, -1, 0] for the paper's crystal)");
  p.lateral = Indices{0, 0, 0};
  if (!lateral.empty()) read_direction(v, "loading.lateral", lateral, p.lattice, p.lateral);
  if (p.lateral != Indices{0, 0, 0} && p.axis != Indices{0, 0, 0}) {
    const Vec3 x = direction_vector(p.lattice, p.lateral, 1).normalized(), z = direction_vector(p.lattice, p.axis, 1).normalized();
    v.require(std::abs(x.dot(z)) < 1e-9, "loading.lateral",
              "'loading.lateral' must be normal to 'loading.axis' (the cosine between them is " + std::to_string(x.dot(z)) +
                  ")");
  }
  v.number("confining_pressure", p.confining_pressure, {0, 1e8, true}, "Pa", "p0, the vacuum bag's pressure");
  v.number("mass_scaling", p.mass_scaling, {1, 1e8}, "-", "density factor");
  p.wall_friction = p.material.friction;
  v.number("wall_friction", p.wall_friction, {0, 10}, "-",
           "Coulomb coefficient between spheres and the two platens (default: material.friction)");

  // The clump must fit its grain (the truncated octahedron's squares refuse too few, too large spheres).
  std::string grain_error;
  if (p.grain.edge_spheres >= 2 && p.grain.overlap >= 0 && p.grain.overlap < 1 && p.grain.size > 0) {
    try {
      const GrainTemplate check(p.grain);
    } catch (const std::exception& e) {
      grain_error = e.what();
    }
  }
  v.require(grain_error.empty(), "grain.edge_spheres", "'grain.edge_spheres': " + grain_error);
  // The pre-strain that carries p0 must stay a small elastic overlap.
  const double prestrain = grain_error.empty() ? hydrostatic_prestrain(p) : 0.0;
  v.require(prestrain <= 0.02, "loading.confining_pressure",
            "'loading.confining_pressure' gives a pre-strain eps0 = " + std::to_string(prestrain) +
                " > 0.02 (sqrt2 p0 / E for fcc): lower it or raise 'material.youngs_modulus'");
  // Memory: about 60 bytes per sphere; 5e7 spheres is 3 GB.
  const double spheres = double(p.grains_x) * p.rows_z * p.layers_y * double(sphere_count(p.grain));
  v.require(spheres <= 5e7, "crystal",
            "'crystal' would hold " + std::to_string(long(spheres)) +
                " spheres (grains_x x rows_z x layers_y x spheres per grain); the limit is 50,000,000");
  // A crystal along a general axis must be one that can be cut: an axis with a normal lattice direction, a box
  // whose site search stays bounded, knock-outs among the sites it holds. Built here once, so that the
  // spec's error names the field rather than the job failing later.
  if (grain_error.empty() && spheres <= 5e7 && p.axis != Indices{0, 0, 0} &&
      !papers_crystal(p.lattice, p.axis, p.lateral)) {
    CrystalGeometry g;
    g.lattice = p.lattice, g.axis = p.axis, g.lateral = p.lateral;
    g.size = p.grain.size, g.prestrain = prestrain;
    g.grains_x = p.grains_x, g.rows_z = p.rows_z, g.layers_y = p.layers_y;
    g.knockout_ids = p.knockout_ids;
    std::string error;
    try {
      build_crystal(g);
    } catch (const std::exception& e) {
      error = e.what();
    }
    const char* field = error.rfind("knock-out", 0) == 0                        ? "crystal.knockout"
                        : error.find("loading.lateral") != std::string::npos ? "loading.lateral"
                                                                              : "loading.axis";
    v.require(error.empty(), field, "'" + std::string(field) + "': " + error);
  }
}

}  // namespace granulab
