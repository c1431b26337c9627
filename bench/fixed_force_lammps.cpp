// The granulab side of bench/fixed_force_compare.py: the paper's fixed-force confinement written for LAMMPS.
// A crystal sample (engine/crystal/crystal_sample.h: lattice pre-strained by eps0 = sqrt2 p0 / E, platens just
// touching its end rows) as built, before any step, and the constant force on every surface grain:
// -p0 x the vector area of its exposed faces (faces whose lattice neighbour is missing), end grains included,
// so the forces add up to zero and the platens start touching and carry only the deviator. Each grain's force
// is split between two antipodal spheres of its clump, so it has no torque about the centre.
//
// Which faces are exposed, and which of them are end faces: engine/crystal/exposed_faces.h (the same forces
// as granulab's loading.confinement = "face_forces").
//
// --lateral in_plane drops the axial (z) component of the lateral faces' forces; --ends cross_section scales
// the end faces' axial forces so that each end carries p0 x the lattice cross-section (what granulab's
// fixed_forces loads them with) instead of p0 x their projected area; --distribution bag replaces them all by
// granulab's fixed_forces ones (the bag's, at the grains' centres) on the sample as built. They are for
// finding which part of the set-up moves the curve.
//
// Writes DIR/data.grains, DIR/bodies.rigid, DIR/forces.lmp (LAMMPS set commands: each pushed sphere's fx fy fz),
// DIR/params.txt (contact constants, platen planes, the top platen's speed, steps, the cross-section, p0 and
// the end loads) and prints a summary.
// Usage: fixed_force_lammps --out DIR [--grains X,Z,Y] [--edge-spheres N] [--overlap K] [--pressure Pa]
//                           [--damping Z] [--friction F] [--rate R] [--max-strain E] [--records N]
//                           [--lateral vector|in_plane] [--ends vector|cross_section] [--distribution vector|bag]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/lammps_files.h"
#include "engine/crystal/crystal_sample.h"
#include "engine/crystal/exposed_faces.h"

using namespace granulab;

namespace {

struct Options {
  std::string out;
  int grains[3] = {3, 7, 4};  // grains_x, rows_z, layers_y
  int edge_spheres = 4, records = 300;
  double overlap = 0.75, pressure = 60e3, damping = 0.1, friction = 0.35, rate = 2e-5, max_strain = 0.03;
  bool lateral_in_plane = false, ends_cross_section = false, bag = false;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument("missing value after " + a);
    const std::string v = argv[++i];
    if (a == "--out") o.out = v;
    else if (a == "--grains") {
      std::stringstream in(v);
      char comma;
      if (!(in >> o.grains[0] >> comma >> o.grains[1] >> comma >> o.grains[2])) throw std::invalid_argument("--grains X,Z,Y");
    } else if (a == "--edge-spheres") o.edge_spheres = std::stoi(v);
    else if (a == "--records") o.records = std::stoi(v);
    else if (a == "--overlap") o.overlap = std::stod(v);
    else if (a == "--pressure") o.pressure = std::stod(v);
    else if (a == "--damping") o.damping = std::stod(v);
    else if (a == "--friction") o.friction = std::stod(v);
    else if (a == "--rate") o.rate = std::stod(v);
    else if (a == "--max-strain") o.max_strain = std::stod(v);
    else if (a == "--lateral") o.lateral_in_plane = v == "in_plane";
    else if (a == "--ends") o.ends_cross_section = v == "cross_section";
    else if (a == "--distribution") o.bag = v == "bag";
    else throw std::invalid_argument("unknown option " + a);
  }
  if (o.out.empty()) throw std::invalid_argument("--out DIR is required");
  return o;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  CrystalSampleParams p;
  p.grain = {Shape::rhombic_dodecahedron, 0.01, o.edge_spheres, o.overlap};
  p.material.damping = o.damping;
  p.material.friction = o.friction;
  p.wall_friction = o.friction;
  p.grains_x = o.grains[0], p.rows_z = o.grains[1], p.layers_y = o.grains[2];
  p.confining_pressure = o.pressure;
  p.time_step_factor = 0.2;  // the granulab side's (fixed_force_compare.py), whatever the crystals' default
  CrystalSample sample(p);
  const World& world = std::as_const(sample).world();
  const Bodies& bodies = world.bodies();
  const GrainTemplate& grain = world.grain();
  const std::size_t n = bodies.size(), per = grain.sphere_count();

  // Exposed faces' vector areas, split into lateral and end parts (what CrystalSample::fix_face_forces uses).
  const double eps0 = hydrostatic_prestrain(p.confining_pressure, p.material.youngs_modulus);
  const std::vector<ExposedArea> exposed = exposed_face_areas(sample.lattice(), grain.solid(), (1 - eps0) * p.grain.size);
  std::vector<Vec3> lateral(n), end(n);
  for (std::size_t b = 0; b < n; ++b) lateral[b] = exposed[b].lateral, end[b] = exposed[b].end;
  // Forces: -p0 x vector area, and the summary's totals.
  std::vector<Vec3> force(n, Vec3::Zero());
  double end_area_top = 0, end_area_bottom = 0;
  for (std::size_t b = 0; b < n; ++b) {
    if (o.lateral_in_plane) lateral[b].z() = 0;
    (end[b].z() > 0 ? end_area_top : end_area_bottom) += std::abs(end[b].z());
  }
  const double cross_section = sample.cross_section();
  for (std::size_t b = 0; b < n; ++b) {
    Vec3 e = end[b];
    if (o.ends_cross_section) e.z() *= cross_section / (e.z() > 0 ? end_area_top : end_area_bottom);
    force[b] = -p.confining_pressure * (lateral[b] + e);
  }
  if (o.bag) {
    // granulab's fixed_forces distribution on the sample as built: the bag's forces (each lateral grain p0 x
    // the area it shows the bag, along the face normal), moved to the grains' centres, and the ends' p0 x
    // cross-section shared by projected area (CrystalSample::fix_confining_forces).
    sample.fix_confining_forces(p.confining_pressure * sample.cross_section());
    force = sample.world().external_force();
  }
  Vec3 net = Vec3::Zero();
  std::size_t pushed = 0;
  for (const Vec3& f : force) net += f, pushed += f.squaredNorm() > 0;

  // Two antipodal spheres of the clump: the first one and the one opposite it.
  const std::vector<Vec3>& offsets = grain.offsets();
  std::size_t opposite = 0;
  for (std::size_t i = 1; i < per; ++i)
    if ((offsets[i] + offsets[0]).norm() < (offsets[opposite] + offsets[0]).norm()) opposite = i;
  if ((offsets[opposite] + offsets[0]).norm() > 1e-12) throw std::runtime_error("the clump has no antipodal pair");

  // Platens: the sample's, just touching the end rows, opened by half a step of the top's travel so that the
  // coplanar end spheres start at a definite overlap in both codes (bench_compare, main()).
  const double speed = o.rate * std::sqrt(p.material.youngs_modulus / p.material.density);
  const double dt = world.settings().time_step, gap = 0.5 * speed * dt;
  const double top = world.walls()[sample.top_wall()].point.z() + gap;
  const double bottom = world.walls()[sample.bottom_wall()].point.z() - gap;
  const double length = top - bottom;
  const auto steps = std::uint64_t(std::ceil(o.max_strain * length / (speed * dt)));

  const std::vector<Vec3>& spheres = world.sphere_positions();
  Vec3 lo = spheres.front(), hi = lo;
  for (const Vec3& x : spheres) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  lo.array() -= 2 * p.grain.size, hi.array() += 2 * p.grain.size;
  bench::write_grains(o.out, world, p.material.density, lo, hi,
                      "granulab fixed_force_lammps: " + std::to_string(n) + " rhombic dodecahedra, " +
                          std::to_string(per) + " spheres each");
  {
    // LAMMPS "set" commands for the pushed spheres (custom per-atom properties d_fx, d_fy, d_fz).
    std::ofstream f(o.out + "/forces.lmp");
    f.precision(17);
    for (std::size_t b = 0; b < n; ++b) {
      if (force[b].squaredNorm() == 0) continue;
      const Vec3 share = force[b] / 2;
      for (std::size_t i : {std::size_t(0), opposite})
        f << "set atom " << b * per + i + 1 << " d_fx " << share.x() << " d_fy " << share.y() << " d_fz " << share.z()
          << "\n";
    }
  }
  std::ofstream f(o.out + "/params.txt");
  f.precision(17);
  bench::write_contact_params(f, world, p.material.density);
  auto put = [&](const char* k, double v) { f << k << ' ' << v << "\n"; };
  put("wall_friction", p.wall_friction);
  put("confining_pressure", p.confining_pressure);
  put("cross_section", cross_section);
  put("end_area_top", end_area_top);
  put("end_area_bottom", end_area_bottom);
  put("wall_zlo", bottom);
  put("wall_zhi", top);
  put("length", length);
  put("top_speed", speed);
  put("steps", double(steps));
  put("record_every", double(std::max<std::uint64_t>(1, steps / o.records)));
  std::printf("%zu grains, %zu spheres (%zu per grain), %zu pushed; dt %.4g s, %llu steps to %.3g %% at %.4g m/s\n", n,
              spheres.size(), per, pushed, dt, (unsigned long long)steps, 100 * o.max_strain, speed);
  std::printf("end projected areas over the cross-section: top %.4f, bottom %.4f%s; net fixed force %.3g N (p0 A = %.4g N)\n",
              end_area_top / cross_section, end_area_bottom / cross_section,
              o.ends_cross_section ? " (scaled to 1)" : "", net.norm(), p.confining_pressure * cross_section);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "fixed_force_lammps: %s\n", e.what());
  return 1;
}
