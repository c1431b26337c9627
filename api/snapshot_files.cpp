#include "api/snapshot_files.h"

#include <cstdio>
#include <unordered_map>

namespace granulab::api {

namespace {

void append(std::string& out, const char* fmt, double a, double b, double c) {
  char buf[128];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  out += buf;
}

template <class F>
std::vector<double> column(std::size_t n, F f) {
  std::vector<double> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = f(i);
  return v;
}

}  // namespace

nlohmann::json snapshot_json(const GrainSnapshot& s) {
  const std::size_t n = s.id.size();
  nlohmann::json grains;
  std::vector<std::uint32_t> ids;
  for (GrainId id : s.id) ids.push_back(value(id));
  grains["id"] = ids;
  for (int k = 0; k < 3; ++k) {
    const char* axis[] = {"x", "y", "z"};
    grains[axis[k]] = column(n, [&](std::size_t i) { return s.position[i][k]; });
    grains[std::string("d") + axis[k]] = column(n, [&](std::size_t i) { return s.displacement[i][k]; });
  }
  grains["qw"] = column(n, [&](std::size_t i) { return s.orientation[i].w(); });
  grains["qx"] = column(n, [&](std::size_t i) { return s.orientation[i].x(); });
  grains["qy"] = column(n, [&](std::size_t i) { return s.orientation[i].y(); });
  grains["qz"] = column(n, [&](std::size_t i) { return s.orientation[i].z(); });
  grains["penetration"] = s.penetration;
  grains["penetration_ratio"] = s.penetration_ratio;
  grains["max_shear_strain"] = s.max_shear_strain;
  grains["equivalent_strain"] = s.equivalent_strain;
  nlohmann::json interfaces;
  interfaces["a"] = column(s.interfaces.size(), [&](std::size_t i) { return double(value(s.interfaces[i].a)); });
  interfaces["b"] = column(s.interfaces.size(), [&](std::size_t i) { return double(value(s.interfaces[i].b)); });
  interfaces["sliding"] = s.sliding;
  return {{"strain", s.strain}, {"step", s.step}, {"grains", grains}, {"interfaces", interfaces}};
}

std::string snapshot_lammps_dump(const GrainSnapshot& s) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& x : s.position) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  std::string out = "ITEM: TIMESTEP\n" + std::to_string(s.step) + "\nITEM: NUMBER OF ATOMS\n" +
                    std::to_string(s.id.size()) + "\nITEM: BOX BOUNDS ff ff ff\n";
  for (int k = 0; k < 3; ++k) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.9g %.9g\n", lo[k], hi[k]);
    out += buf;
  }
  out += "ITEM: ATOMS id x y z dx dy dz quatw quati quatj quatk penetration penetration_ratio max_shear_strain "
         "equivalent_strain\n";
  char line[512];
  for (std::size_t i = 0; i < s.id.size(); ++i) {
    const Vec3 &x = s.position[i], &d = s.displacement[i];
    const Quat& q = s.orientation[i];
    std::snprintf(line, sizeof line, "%u %.9g %.9g %.9g %.6g %.6g %.6g %.9g %.9g %.9g %.9g %.6g %.6g %.6g %.6g\n",
                  value(s.id[i]), x.x(), x.y(), x.z(), d.x(), d.y(), d.z(), q.w(), q.x(), q.y(), q.z(), s.penetration[i],
                  s.penetration_ratio[i], s.max_shear_strain[i], s.equivalent_strain[i]);
    out += line;
  }
  return out;
}

std::string snapshot_grains_vtk(const GrainSnapshot& s) {
  const std::size_t n = s.id.size();
  std::string out = "# vtk DataFile Version 3.0\ngranulab grains, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET POLYDATA\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& x : s.position) append(out, "%.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  out += "VERTICES " + std::to_string(n) + " " + std::to_string(2 * n) + "\n";
  for (std::size_t i = 0; i < n; ++i) out += "1 " + std::to_string(i) + "\n";
  out += "POINT_DATA " + std::to_string(n) + "\nSCALARS id int 1\nLOOKUP_TABLE default\n";
  for (GrainId id : s.id) out += std::to_string(value(id)) + "\n";
  out += "VECTORS displacement double\n";
  for (const Vec3& d : s.displacement) append(out, "%.6g %.6g %.6g\n", d.x(), d.y(), d.z());
  auto scalars = [&](const char* name, const std::vector<double>& v) {
    out += std::string("SCALARS ") + name + " double 1\nLOOKUP_TABLE default\n";
    char buf[40];
    for (double x : v) std::snprintf(buf, sizeof buf, "%.6g\n", x), out += buf;
  };
  scalars("penetration", s.penetration);
  scalars("penetration_ratio", s.penetration_ratio);
  scalars("max_shear_strain", s.max_shear_strain);
  scalars("equivalent_strain", s.equivalent_strain);
  out += "FIELD orientation 1\nquaternion_wxyz 4 " + std::to_string(n) + " double\n";
  char buf[128];
  for (const Quat& q : s.orientation) std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g\n", q.w(), q.x(), q.y(), q.z()), out += buf;
  return out;
}

std::string snapshot_interfaces_vtk(const GrainSnapshot& s) {
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.id.size(); ++i) index[value(s.id[i])] = i;
  const std::size_t n = s.id.size(), m = s.interfaces.size();
  std::string out = "# vtk DataFile Version 3.0\ngranulab interfaces, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET POLYDATA\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& x : s.position) append(out, "%.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  out += "LINES " + std::to_string(m) + " " + std::to_string(3 * m) + "\n";
  for (const auto& [a, b] : s.interfaces)
    out += "2 " + std::to_string(index[value(a)]) + " " + std::to_string(index[value(b)]) + "\n";
  out += "CELL_DATA " + std::to_string(m) + "\nSCALARS sliding double 1\nLOOKUP_TABLE default\n";
  char buf[40];
  for (double x : s.sliding) std::snprintf(buf, sizeof buf, "%.6g\n", x), out += buf;
  return out;
}

}  // namespace granulab::api
