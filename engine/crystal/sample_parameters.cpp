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

// loading.axis and loading.lateral: the compression axis (lab z) and the sample's x axis.
void visit_compression_axes(ParameterVisitor& v, CrystalSampleParams& p) {
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
}

// A plane's Miller indices from the spec: three (h, k, l), or for HCP also the four (h, k, i, l) with i = -(h + k).
void read_plane(ParameterVisitor& v, const char* field, const std::vector<double>& in, LatticeType lattice,
                Indices& out) {
  const bool four = lattice == LatticeType::hcp && in.size() == 4;
  const bool sized = in.size() == 3 || four;
  v.require(sized, field,
            std::string("'") + field + "' must hold three Miller indices [h, k, l]" +
                (lattice == LatticeType::hcp ? " or four [h, k, i, l]" : ""));
  if (!sized) return;
  const bool whole = std::all_of(in.begin(), in.end(), integral);
  v.require(whole, field, std::string("'") + field + "' must hold integers (Miller indices)");
  if (!whole) return;
  const long h = std::lround(in[0]), k = std::lround(in[1]);
  if (four)
    v.require(std::lround(in[2]) == -(h + k), field,
              std::string("'") + field + "' in four indices [h, k, i, l] needs i = -(h + k)");
  out = Indices{int(h), int(k), int(std::lround(in[four ? 3 : 2]))};
}

// A shear slab of about 4 a x 4 a across and four to six layers along the normal, for the default plane and
// direction of each lattice (docs/spec.md): fcc (1 1 1) [1 -1 0] 6 x 20 x 2 repeats of 0.71 a, 0.20 a and three
// layers; sc (1 0 0) [0 1 0] 4 x 4 x 5 cubes; bcc (1 1 0) [1 -1 1] 5 x 10 x 3 repeats of 0.87 a, 0.41 a and two
// layers; hcp (0 0 0 1) [2 -1 -1 0] 6 x 7 x 3 repeats of 0.71 a, 0.61 a and two layers.
void shear_box_defaults(CrystalSampleParams& p) {
  switch (p.lattice) {
    case LatticeType::fcc: p.grains_x = 6, p.layers_y = 20, p.rows_z = 2; break;
    case LatticeType::sc: p.grains_x = 4, p.layers_y = 4, p.rows_z = 5; break;
    case LatticeType::bcc: p.grains_x = 5, p.layers_y = 10, p.rows_z = 3; break;
    case LatticeType::hcp: p.grains_x = 6, p.layers_y = 7, p.rows_z = 3; break;
  }
}

// A shear's loading.plane and loading.direction: the plane's normal becomes the sample's axis (lab z), the
// direction, which must lie in the plane, its x axis.
void visit_shear_axes(ParameterVisitor& v, CrystalSampleParams& p, Indices& plane) {
  std::vector<double> given = p.lattice == LatticeType::fcc ? std::vector<double>{1, 1, 1}
                              : p.lattice == LatticeType::sc ? std::vector<double>{1, 0, 0}
                              : p.lattice == LatticeType::bcc ? std::vector<double>{1, 1, 0}
                                                               : std::vector<double>{0, 0, 0, 1};
  v.numbers("plane", given, {-12, 12}, 4, "-",
            "the shear plane's Miller indices (h, k, l): cubic for sc, fcc and bcc; for hcp of a1, a2, c, or the four "
            "(h, k, i, l) (default: (1, 1, 1) fcc, (1, 0, 0) sc, (1, 1, 0) bcc, (0, 0, 0, 1) hcp); its normal is the "
            "sample's z axis");
  plane = Indices{0, 0, 0};
  read_plane(v, "loading.plane", given, p.lattice, plane);
  v.require(plane != Indices{0, 0, 0}, "loading.plane", "'loading.plane' must not be (0, 0, 0)");
  if (plane != Indices{0, 0, 0}) {
    std::string error;
    try {
      p.axis = normal_direction(p.lattice, plane);
    } catch (const std::exception& e) {
      error = e.what();
    }
    v.require(error.empty(), "loading.plane", "'loading.plane': " + error);
  }
  std::vector<double> direction = p.lattice == LatticeType::fcc ? std::vector<double>{1, -1, 0}
                                  : p.lattice == LatticeType::sc ? std::vector<double>{0, 1, 0}
                                  : p.lattice == LatticeType::bcc ? std::vector<double>{1, -1, 1}
                                                                   : std::vector<double>{2, -1, -1, 0};
  v.numbers("direction", direction, {-12, 12}, 4, "-",
            "the shear direction, a lattice direction [u, v, w] in the plane (the top layer moves along it: the sample's x "
            "axis): cubic indices, for hcp of a1, a2, c or the four-index [U, V, T, W] (default: [1, -1, 0] fcc, [0, 1, 0] "
            "sc, [1, -1, 1] bcc, [2, -1, -1, 0] hcp)");
  p.lateral = Indices{0, 0, 0};
  read_direction(v, "loading.direction", direction, p.lattice, p.lateral);
  v.require(p.lateral != Indices{0, 0, 0}, "loading.direction", "'loading.direction' must not be [0, 0, 0]");
  if (p.lateral != Indices{0, 0, 0} && plane != Indices{0, 0, 0}) {
    const double cosine = direction_vector(p.lattice, p.lateral, 1).normalized().dot(plane_normal(p.lattice, plane));
    v.require(std::abs(cosine) < 1e-9, "loading.direction",
              "'loading.direction' must lie in 'loading.plane' (the cosine between it and the plane's normal is " +
                  std::to_string(cosine) + ")");
  }
}

}  // namespace

void visit_crystal_sample(ParameterVisitor& v, CrystalSampleParams& p, Indices* shear_plane) {
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
  visit_integration(v, p.time_step_factor, p.skin_factor, p.kernel);
  v.number("local_damping", p.local_damping, {0, 0.99}, "-",
           "lambda of each grain's local (non-viscous) damping: every component of its net force loses lambda times "
           "its magnitude against that component of its velocity (Yade's NewtonIntegrator.damping); 0: none, the "
           "paper's model (docs/model.md, \"Local damping\")");
  if (p.local_damping_rotational < 0) p.local_damping_rotational = p.local_damping;
  v.number("local_damping_rotational", p.local_damping_rotational, {0, 0.99}, "-",
           "the same for its net torque against its angular velocity (default: run.local_damping)");
  std::string dashpots = p.damping_velocity == DampingVelocity::quarter_step ? "quarter_step" : "half_step";
  v.choice("damping_velocity", dashpots, {"half_step", "quarter_step"},
           "the velocity the contacts' dashpots see at a step's force evaluation: quarter_step, v(t) + a(t) dt/4, stable "
           "and converged at the default run.time_step_factor 0.3 on the paper's N_e = 10 crystal; half_step, velocity "
           "Verlet's v(t + dt/2) as in LAMMPS, which on that crystal needs about 0.1 to converge (docs/model.md, "
           "\"Time step\", \"Damping velocity\")");
  p.damping_velocity = dashpots == "quarter_step" ? DampingVelocity::quarter_step : DampingVelocity::half_step;

  v.section("crystal");
  if (shear_plane) shear_box_defaults(p);
  v.integer("grains_x", p.grains_x, 1, 100, "grains per row (x): the box is grains_x lattice repeats along x");
  v.integer("rows_z", p.rows_z, 1, 400,
            shear_plane ? "rows along the shear plane's normal (z), each a lattice repeat: the box holds about grains_x x "
                          "layers_y x rows_z grains"
                        : "rows along the compression axis (z): the box holds about grains_x x layers_y x rows_z grains");
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
  if (shear_plane) visit_shear_axes(v, p, *shear_plane);
  else visit_compression_axes(v, p);
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
                        : error.find("loading.lateral") != std::string::npos ? (shear_plane ? "loading.direction"
                                                                                            : "loading.lateral")
                        : shear_plane                                         ? "loading.plane"
                                                                              : "loading.axis";
    v.require(error.empty(), field, "'" + std::string(field) + "': " + error);
  }
}

}  // namespace granulab
