#include "bench/lammps_files.h"

#include <filesystem>
#include <fstream>

namespace granulab::bench {

void write_grains(const std::string& dir, const World& world, double density, const Vec3& lo, const Vec3& hi,
                  const std::string& title) {
  std::filesystem::create_directories(dir);
  const Bodies& bodies = world.bodies();
  const std::vector<Vec3>& spheres = world.sphere_positions();
  const std::size_t per = world.grain().sphere_count();
  const double d = world.grain().diameter();
  {
    std::ofstream f(dir + "/data.grains");
    f.precision(17);
    f << title << "\n\n" << spheres.size() << " atoms\n1 atom types\n\n";
    f << lo.x() << ' ' << hi.x() << " xlo xhi\n"
      << lo.y() << ' ' << hi.y() << " ylo yhi\n"
      << lo.z() << ' ' << hi.z() << " zlo zhi\n\n";
    f << "Atoms # sphere\n\n";
    for (std::size_t s = 0; s < spheres.size(); ++s)
      f << s + 1 << " 1 " << d * bodies.scale[s / per] << ' ' << density << ' ' << spheres[s].x() << ' '
        << spheres[s].y() << ' ' << spheres[s].z() << "\n";
    f << "\nMolecules\n\n";
    for (std::size_t s = 0; s < spheres.size(); ++s) f << s + 1 << ' ' << s / per + 1 << "\n";
  }
  std::ofstream f(dir + "/bodies.rigid");
  f.precision(17);
  f << "# granulab grains: id mass xcm ycm zcm ixx iyy izz ixy ixz iyz vxcm vycm vzcm lx ly lz ixcm iycm izcm\n";
  f << "# mass = density x polyhedron volume, inertia of the solid polyhedron (not of the overlapping spheres)\n";
  f << bodies.size() << "\n";
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    // Lab-frame inertia tensor R diag(I) R^T (isotropic for the RD).
    const Mat3 r = bodies.orientation[b].toRotationMatrix();
    const Mat3 in = r * bodies.inertia[b].asDiagonal() * r.transpose();
    const Vec3& x = bodies.position[b];
    f << b + 1 << ' ' << bodies.mass[b] << ' ' << x.x() << ' ' << x.y() << ' ' << x.z() << ' ' << in(0, 0) << ' '
      << in(1, 1) << ' ' << in(2, 2) << ' ' << in(0, 1) << ' ' << in(0, 2) << ' ' << in(1, 2)
      << " 0 0 0 0 0 0 0 0 0\n";
  }
}

void write_contact_params(std::ostream& f, const World& world, double density) {
  const ContactLaw& law = world.law();
  const double m = world.bodies().mass[0];
  // Our c_n = 2 zeta sqrt(k_n m_eff) is LAMMPS' m_eff gamma_n; c_t = c_n / 2.
  const double gamma_pair = damping_coefficient(law, m / 2) / (m / 2);
  const double gamma_wall = damping_coefficient(law, m) / m;
  const GrainTemplate& grain = world.grain();
  auto put = [&](const char* k, double v) { f << k << ' ' << v << "\n"; };
  put("grains", double(world.bodies().size()));
  put("spheres", double(world.sphere_count()));
  put("spheres_per_grain", double(grain.sphere_count()));
  put("diameter", grain.diameter());
  put("grain_size", grain.geometry().size);
  put("grain_mass", m);
  put("grain_inertia", world.bodies().inertia[0].x());
  put("density", density);
  put("kn", law.normal_stiffness);
  put("kt", law.tangential_stiffness);
  put("damping_ratio", law.damping_ratio);
  put("gamma_n_pair", gamma_pair);
  put("gamma_t_pair", gamma_pair / 2);
  put("gamma_n_wall", gamma_wall);
  put("gamma_t_wall", gamma_wall / 2);
  put("friction", law.friction);
  put("dt", world.settings().time_step);
  put("skin", world.settings().skin);
  put("bounding_radius", grain.bounding_radius());
}

}  // namespace granulab::bench
