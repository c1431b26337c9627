#include "engine/model/model_parameters.h"

namespace granulab {

void visit_grain(ParameterVisitor& v, GrainGeometry& g) {
  v.section("grain");
  // Each experiment has one grain shape: cubes slide in section 3, dodecahedra tile the crystal.
  std::string shape = to_string(g.shape);
  v.choice("shape", shape, {to_string(g.shape)}, "grain shape (one per experiment)");
  v.number("size", g.size, {0, 1, true}, "m", "cube side l, or RD cubic cell a");
  v.integer("edge_spheres", g.edge_spheres, 2, 40, "N_e, spheres along every edge");
  v.number("overlap", g.overlap, {0, 0.95}, "-", "kappa; sphere spacing s = d(1 - kappa)");
}

void visit_material(ParameterVisitor& v, Material& m) {
  v.section("material");
  v.number("youngs_modulus", m.youngs_modulus, {0, 1e13, true}, "Pa", "E; sets k_n = E / (rho_s size) (eqs. 5, 6, 8)");
  v.number("density", m.density, {0, 1e5, true}, "kg/m^3", "mass and inertia of the solid polyhedron");
  v.number("friction", m.friction, {0, 10}, "-", "Coulomb f, sphere-sphere and sphere-wall");
  v.number("tangential_stiffness_ratio", m.tangential_stiffness_ratio, {0, 1}, "-", "k_t / k_n");
  v.number("damping", m.damping, {0, 0.99}, "-", "zeta, fraction of critical damping of one sphere pair");
}

void visit_integration(ParameterVisitor& v, double& time_step_factor, double& skin_factor) {
  v.section("run");
  v.number("time_step_factor", time_step_factor, {0, 0.5, true}, "-", "dt / t0, t0 = sqrt(m / (E A_face / size))");
  v.number("skin_factor", skin_factor, {0, 1, true}, "-", "neighbour-list skin / d");
}

}  // namespace granulab
