// The granulab side of bench/lammps_laws_compare.py (issue 29): the force-overlap curve of one interface law
// (contact.normal hertz/material, dmt or jkr; contact.tangential linear_history) between two aligned cubes held at
// rest face to face, as tests/engine/validation/interface_laws_test.cpp sets them up: GrainTemplate cube, edge
// 0.01 m, N_e = 4, kappa = 0.75, E = 3e9 Pa, nu = 0.3, gamma from the command line. Cube 0 sits at the origin,
// cube 1 on +x at 2 x_face + d - delta, so that its facing sphere layer overlaps cube 0's by delta (negative: apart).
// At each delta the bodies are at rest and World::compute_forces() gives the force; the sweep is
//   phase "in":  delta from --from to --to (units of s, below), pressing in from apart,
//   phase "out": delta from --to down to --pull-to, pulling back out past JKR's break point,
// each with --points points, half a step off the round numbers (so no point sits on delta = 0 or -delta_c, where
// rounding would decide). The unit s is JKR's break depth delta_c = a_c^2 / (3 R*), a_c^3 = 9 pi gamma R*^2 / (4 E*),
// at the given gamma (at gamma = 5 J/m^2 when gamma is 0), the same for every law so their curves share the axis.
//
// stdout: CSV "phase,delta_m,force_N" (force = the x-force on cube 1, compressive positive), 17 digits.
// --write-lammps DIR: DIR/data.grains (read_data, atom_style sphere, molecule = cube; lammps_files.h) with cube 1 at
// delta = 0 (x = 2 x_face + d), so LAMMPS moves it by -delta, and DIR/params.txt ("key value": the law, E, nu,
// gamma, E*, R*, the aligned pairs n_c, k_t, friction, s, closed forms of the pull-off forces, the box).
//
// Usage: bench_interface_laws --law hertz/material|dmt|jkr [--gamma G] [--youngs E] [--poisson NU] [--points N]
//                             [--from A] [--to B] [--pull-to C] [--write-lammps DIR]
// LAMMPS is a comparison tool only: nothing here links to or needs it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "bench/machine.h"
#include "bench/lammps_files.h"
#include "engine/model/model.h"
#include "engine/world/world.h"

using namespace granulab;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Options {
  std::string law = "jkr";
  double gamma = 5, youngs = 3e9, poisson = 0.3;
  int points = 600;
  double from = -2, to = 4, pull_to = -2.5;  // in units of s
  std::string lammps_dir;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--law") o.law = next();
    else if (a == "--gamma") o.gamma = std::stod(next());
    else if (a == "--youngs") o.youngs = std::stod(next());
    else if (a == "--poisson") o.poisson = std::stod(next());
    else if (a == "--points") o.points = std::stoi(next());
    else if (a == "--from") o.from = std::stod(next());
    else if (a == "--to") o.to = std::stod(next());
    else if (a == "--pull-to") o.pull_to = std::stod(next());
    else if (a == "--write-lammps") o.lammps_dir = next();
    else throw std::runtime_error("unknown option " + a);
  }
  if (o.points < 2) throw std::runtime_error("--points must be at least 2");
  if (!(o.from < o.to) || !(o.pull_to < o.to)) throw std::runtime_error("need --from < --to and --pull-to < --to");
  return o;
}

}  // namespace

int main(int argc, char** argv) try {
  granulab::print_machine(stderr);  // stdout is the CSV
  const Options o = parse(argc, argv);
  NormalModel normal;
  if (!normal_model_from_string(o.law, normal) ||
      !(normal == NormalModel::hertz_material || normal == NormalModel::dmt || normal == NormalModel::jkr))
    throw std::runtime_error("--law must be hertz/material, dmt or jkr");

  const GrainTemplate cube{GrainGeometry{Shape::cube, 0.01, 4, 0.75}};
  Material material;
  material.youngs_modulus = o.youngs;
  material.contact.normal = normal;
  material.contact.poisson_ratio = o.poisson;
  material.contact.surface_energy = normal == NormalModel::hertz_material ? 0.0 : o.gamma;
  material.friction = 0.3;
  const ContactLaw law = contact_law(cube, material);
  const double d = cube.diameter();
  // As the test: dt 1e-7 s (unused at rest), skin 0.05 d.
  World world(cube, law, {1e-7, 0.05 * d, Vec3::Zero()});

  double face_x = 0;
  for (const Vec3& off : cube.offsets()) face_x = std::max(face_x, off.x());
  int aligned = 0;
  for (const Vec3& off : cube.offsets()) aligned += std::abs(off.x() - face_x) < 1e-12 * face_x;
  const double x_touch = 2 * face_x + d;  // cube 1's x at delta = 0
  world.add_grain(Vec3::Zero(), Quat::Identity(), material.density);
  world.add_grain(Vec3(x_touch, 0, 0), Quat::Identity(), material.density);

  const double r_eff = d / 4, e_star = effective_modulus(o.youngs, o.poisson);
  const double gamma_unit = o.gamma > 0 ? o.gamma : 5.0;
  const double ac = std::cbrt(9 * kPi * gamma_unit * r_eff * r_eff / (4 * e_star));
  const double unit = ac * ac / (3 * r_eff);

  if (!o.lammps_dir.empty()) {
    world.compute_forces();  // sphere positions of the poses above
    const Vec3 lo(-face_x - d, -face_x - d, -face_x - d), hi(x_touch + face_x + d, face_x + d, face_x + d);
    bench::write_grains(o.lammps_dir, world, material.density, lo, hi,
                        "granulab bench_interface_laws: two cubes N_e 4 kappa 0.75, cube 2 at delta = 0");
    std::ofstream f(o.lammps_dir + "/params.txt");
    f.precision(17);
    auto put = [&](const char* k, double v) { f << k << ' ' << v << "\n"; };
    f << "law " << o.law << "\n";
    put("youngs", o.youngs);
    put("poisson", o.poisson);
    put("gamma", material.contact.surface_energy);
    put("effective_modulus", e_star);
    put("r_eff", r_eff);
    put("diameter", d);
    put("spheres_per_grain", double(cube.sphere_count()));
    put("aligned_pairs", aligned);
    put("kt", law.tangential_stiffness);
    put("friction", law.friction);
    put("unit", unit);
    put("skin", world.settings().skin);
    put("x_touch", x_touch);
    put("pulloff_dmt_closed", aligned * 4 * kPi * material.contact.surface_energy * r_eff);
    put("pulloff_jkr_closed", aligned * 3 * kPi * material.contact.surface_energy * r_eff);
    put("break_depth_jkr_closed", law.pulloff_distance(r_eff));
    f << "box " << lo.x() << ' ' << hi.x() << ' ' << lo.y() << ' ' << hi.y() << ' ' << lo.z() << ' ' << hi.z()
      << "\n";
  }

  std::printf("phase,delta_m,force_N\n");
  auto sweep = [&](const char* phase, double a, double b) {
    for (int k = 0; k < o.points; ++k) {
      // Half a step off the grid of round numbers (a + (b - a) k / n), so never exactly at 0 or -delta_c.
      const double delta = unit * (a + (b - a) * (k + 0.5) / o.points);
      world.bodies().position[1] = Vec3(x_touch - delta, 0, 0);
      world.compute_forces();
      std::printf("%s,%.17g,%.17g\n", phase, delta, world.bodies().force[1].x());
    }
  };
  sweep("in", o.from, o.to);
  sweep("out", o.to, o.pull_to);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_interface_laws: %s\n", e.what());
  return 2;
}
