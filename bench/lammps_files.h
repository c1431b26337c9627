// The LAMMPS side of a comparison run, written from a granulab world (bench_compare, fixed_force_lammps):
// the spheres and the rigid bodies they form, and the contact constants in LAMMPS' terms. LAMMPS is a
// comparison tool only: nothing here links to it; the scripts that run it write its input.
#pragma once

#include <ostream>
#include <string>

#include "engine/core/types.h"
#include "engine/world/world.h"

namespace granulab::bench {

/// DIR/data.grains (read_data, atom_style sphere: "id type diameter density x y z" per sphere, plus a
/// "Molecules" section, molecule id = body index + 1, for fix property/atom mol) and DIR/bodies.rigid (fix
/// rigid/small's infile: each body's mass, centre of mass and lab-frame inertia of the solid polyhedron,
/// at rest). The box is [lo, hi]. Sphere ids are body-major, 1-based: sphere i of body b is b * per + i + 1.
void write_grains(const std::string& dir, const World& world, double density, const Vec3& lo, const Vec3& hi,
                  const std::string& title);

/// "key value" lines of the contact law as LAMMPS' gran/hooke/history takes them: kn, kt, gamma_n and
/// gamma_t for a grain pair and for a wall (LAMMPS' damping is m_eff gamma v with m_eff from the bodies'
/// masses: m/2 for a pair of equal grains, m on a wall), friction, dt, skin, sphere diameter, grain size,
/// mass and bounding radius.
void write_contact_params(std::ostream& f, const World& world, double density);

}  // namespace granulab::bench
