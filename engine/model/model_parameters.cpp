#include "engine/model/model_parameters.h"

#include "engine/contact/pair_kernel.h"

namespace granulab {

void visit_grain(ParameterVisitor& v, GrainGeometry& g, const std::vector<Shape>& shapes, const std::string& why) {
  v.section("grain");
  // Each experiment has one grain shape: cubes slide in section 3; a crystal's tile its lattice (crystal.lattice).
  std::string shape = to_string(g.shape);
  std::vector<std::string> names;
  for (Shape s : shapes) names.push_back(to_string(s));
  if (names.empty()) names.push_back(shape);
  v.choice("shape", shape, names, "grain shape (one per experiment; a crystal's follows crystal.lattice)");
  v.require(shape == to_string(g.shape), "grain.shape",
            "'grain.shape' is " + shape + ", but " + (why.empty() ? "this experiment's grains are " : why) +
                to_string(g.shape) + " (leave it out to get them)");
  v.number("size", g.size, {0, 1, true}, "m",
           "cube side l, or the crystal's cubic cell a (hcp: the fcc cell of the same nearest-neighbour distance, D = a / sqrt2)");
  v.integer("edge_spheres", g.edge_spheres, 2, 40,
            "N_e, spheres along every edge (truncated octahedron: its hexagon-hexagon edges; trapezo-rhombic "
            "dodecahedron: its rhombi's edges), spacing s on every other edge and face");
  v.number("overlap", g.overlap, {0, 0.95}, "-", "kappa; sphere spacing s = d(1 - kappa)");
}

void visit_material(ParameterVisitor& v, Material& m) {
  v.section("material");
  v.number("youngs_modulus", m.youngs_modulus, {0, 1e13, true}, "Pa", "E; sets k_n = E / (rho_s size) (eqs. 5, 6, 8)");
  v.number("density", m.density, {0, 1e5, true}, "kg/m^3", "mass and inertia of the solid polyhedron");
  v.number("friction", m.friction, {0, 10}, "-", "Coulomb f, sphere-sphere and sphere-wall");
  v.number("tangential_stiffness_ratio", m.tangential_stiffness_ratio, {0, 1}, "-", "k_t / k_n");
  v.number("damping", m.damping, {0, 0.99}, "-",
           "zeta, fraction of critical damping of one sphere pair (Hertz family: of its tangent stiffness 2 E* a)");
  visit_interface_law(v, m);
}

void visit_interface_law(ParameterVisitor& v, Material& m) {
  InterfaceLaw& c = m.contact;
  v.section("contact");
  std::string normal = to_string(c.normal), tangential = to_string(c.tangential);
  v.choice("normal", normal, normal_model_names(),
           "normal law between spheres, as LAMMPS pair_style granular names it: hooke (the paper's, k_n from the face), "
           "hertz (k_N sqrt(R* delta) delta), hertz/material (k_N = 4/3 E*, E* = E / (2 (1 - nu^2))), dmt (hertz/material "
           "- 4 pi gamma R*), jkr (adhesive, held to the pull-off distance); R* = d / 4 between spheres");
  normal_model_from_string(normal, c.normal);
  v.choice("tangential", tangential, tangential_model_names(),
           "tangential spring: linear_history (k_t = material.tangential_stiffness_ratio x hooke's k_n), mindlin "
           "(k_t a, k_t = 8 G* = 2 E / ((2 - nu) (1 + nu)), a the contact radius)");
  tangential_model_from_string(tangential, c.tangential);
  v.number("poisson_ratio", c.poisson_ratio, {-0.99, 0.5}, "-", "nu of the grains' material (hertz/material, dmt, jkr, mindlin)");
  v.number("surface_energy", c.surface_energy, {0, 1e4}, "J/m^2",
           "gamma as LAMMPS defines it (dmt, jkr): pull-off 4 pi gamma R* (dmt), 3 pi gamma R* (jkr)");
  c.hertz_stiffness = 4.0 / 3 * effective_modulus(m.youngs_modulus, c.poisson_ratio);
  v.number("hertz_stiffness", c.hertz_stiffness, {0, 1e13, true}, "Pa", "k_N of hertz (default 4/3 E*)");
  v.require(!is_cohesive(c.normal) || c.surface_energy > 0, "contact.surface_energy",
            "'contact.surface_energy' must be > 0 for contact.normal " + normal +
                " (without surface energy use hertz/material)");
}

void visit_integration(ParameterVisitor& v, double& time_step_factor, double& skin_factor, std::string& kernel) {
  v.section("run");
  v.number("time_step_factor", time_step_factor, {0, 0.5, true}, "-", "dt / t0, t0 = sqrt(m / (E A_face / size))");
  v.number("skin_factor", skin_factor, {0, 1, true}, "-", "neighbour-list skin / d");
  std::vector<std::string> names{"auto"};
  for (const PairKernelInfo& k : pair_kernels()) names.push_back(k.name);
  v.choice("kernel", kernel, names,
           "the contact kernel's instruction set: auto, the widest this CPU runs (avx512 > avx2 > the baseline); "
           "avx512 (AVX-512 F/CD/DQ/BW/VL), avx2 (AVX2 + FMA), sse2 (the x86-64 baseline) force one, for comparisons. "
           "Kernels differ in their results' last bits only (docs/model.md, \"Contact kernels\"); summary.json names "
           "the one that ran");
  bool runs = true;
  for (const PairKernelInfo& k : pair_kernels())
    if (kernel == k.name) runs = k.runs_here;
  v.require(runs, "run.kernel",
            "'run.kernel' " + kernel + " needs instructions this CPU lacks; it runs " + best_pair_kernel() +
                " and below (or auto)");
}

}  // namespace granulab
