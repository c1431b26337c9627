#include "api/network_files.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

#include "api/legacy_vtk.h"
#include "engine/analysis/snapshot_layers.h"
#include "engine/geometry/grain_template.h"
#include "engine/geometry/polyhedron.h"

namespace granulab::api {

namespace {

std::string number(double v, const char* format = "%.9g") {
  char text[40];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::unordered_map<std::uint32_t, std::size_t> index_of(const GrainSnapshot& s) {
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.id.size(); ++i) index[value(s.id[i])] = i;
  return index;
}

// Per contact: the grains' indices, normal (compressive positive) and tangential force, and the interface's sliding.
struct ContactRow {
  std::size_t a, b;
  Vec3 force;
  double normal, tangential, sliding;
};

std::vector<ContactRow> contact_rows(const GrainSnapshot& s) {
  const auto index = index_of(s);
  std::unordered_map<std::uint64_t, double> sliding;
  const auto key = [](std::uint32_t a, std::uint32_t b) {
    return a < b ? std::uint64_t(a) << 32 | b : std::uint64_t(b) << 32 | a;
  };
  for (std::size_t k = 0; k < s.interfaces.size() && k < s.sliding.size(); ++k)
    sliding[key(value(s.interfaces[k].a), value(s.interfaces[k].b))] = s.sliding[k];
  std::vector<ContactRow> rows;
  for (std::size_t k = 0; k < s.contacts.size() && k < s.contact_force.size(); ++k) {
    const auto a = index.find(value(s.contacts[k].a)), b = index.find(value(s.contacts[k].b));
    if (a == index.end() || b == index.end()) continue;
    const Vec3 branch = s.position[a->second] - s.position[b->second];  // from b to a
    const Vec3 n = branch.norm() > 0 ? Vec3(branch.normalized()) : Vec3::UnitZ();
    const Vec3& f = s.contact_force[k];
    const double fn = f.dot(n);  // pushing a away from b: compression
    const auto slid = sliding.find(key(value(s.contacts[k].a), value(s.contacts[k].b)));
    rows.push_back({a->second, b->second, f, fn, (f - fn * n).norm(), slid == sliding.end() ? 0.0 : slid->second});
  }
  return rows;
}

}  // namespace

std::string snapshot_contacts_vtk(const GrainSnapshot& s) {
  const std::vector<ContactRow> rows = contact_rows(s);
  const std::size_t n = s.id.size(), m = rows.size();
  std::string out = "# vtk DataFile Version 3.0\ngranulab contact network, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& x : s.position) out += number(x.x()) + " " + number(x.y()) + " " + number(x.z()) + "\n";
  std::string lines;
  for (const ContactRow& r : rows) lines += "2 " + std::to_string(r.a) + " " + std::to_string(r.b) + "\n";
  append_cells(out, m, 3 * m, lines, VtkCell::line);
  out += "CELL_DATA " + std::to_string(m) + "\nVECTORS force double\n";
  for (const ContactRow& r : rows)
    out += number(r.force.x(), "%.6g") + " " + number(r.force.y(), "%.6g") + " " + number(r.force.z(), "%.6g") + "\n";
  out += "SCALARS force_normal double 1\nLOOKUP_TABLE default\n";
  for (const ContactRow& r : rows) out += number(r.normal, "%.6g") + "\n";
  // The other arrays in a FIELD block, which every legacy reader reads (api/legacy_vtk.h).
  VtkFieldBlock fields;
  const auto scalars = [&](const char* name, auto get) {
    std::string text;
    for (const ContactRow& r : rows) text += number(get(r), "%.6g") + "\n";
    fields.add(name, 1, m, std::move(text));
  };
  scalars("force_tangential", [](const ContactRow& r) { return r.tangential; });
  scalars("force_magnitude", [](const ContactRow& r) { return std::hypot(r.normal, r.tangential); });
  scalars("sliding", [](const ContactRow& r) { return r.sliding; });
  fields.append_to(out, "contact_fields");
  return out;
}

std::string snapshot_contacts_dump(const GrainSnapshot& s) {
  const std::vector<ContactRow> rows = contact_rows(s);
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& x : s.position) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  if (s.position.empty()) lo = hi = Vec3::Zero();
  std::string out = "ITEM: TIMESTEP\n" + std::to_string(s.step) + "\nITEM: NUMBER OF ENTRIES\n" +
                    std::to_string(rows.size()) + "\nITEM: BOX BOUNDS ff ff ff\n";
  for (int k = 0; k < 3; ++k) out += number(lo[k]) + " " + number(hi[k]) + "\n";
  // grain_a and grain_b are the grains' ids in the grain dump (snapshot_lammps_dump): the grain's id + 1.
  out += "ITEM: ENTRIES index grain_a grain_b fx fy fz force_normal force_tangential sliding\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const ContactRow& r = rows[k];
    const Vec3& f = r.force;
    out += std::to_string(k + 1) + " " + std::to_string(std::uint64_t(value(s.id[r.a])) + 1) + " " +
           std::to_string(std::uint64_t(value(s.id[r.b])) + 1) + " " + number(f.x(), "%.6g") + " " +
           number(f.y(), "%.6g") + " " + number(f.z(), "%.6g") + " " + number(r.normal, "%.6g") + " " +
           number(r.tangential, "%.6g") + " " + number(r.sliding, "%.6g") + "\n";
  }
  return out;
}

std::string snapshot_spheres_dump(const GrainSnapshot& s) {
  if (s.edge_spheres < 2 || !(s.grain_size > 0))
    throw std::invalid_argument("this snapshot was stored before its grains' sphere clumps were kept (no N_e): "
                                "no sphere-level dump");
  const GrainTemplate grain(GrainGeometry{s.grain_shape, s.grain_size, s.edge_spheres, s.sphere_overlap});
  const std::size_t per = grain.sphere_count(), n = s.id.size();
  if (n * per > kMaxDumpSpheres)
    throw std::invalid_argument("a sphere-level dump of " + std::to_string(n * per) + " spheres is over the " +
                                std::to_string(kMaxDumpSpheres) + " this server writes: use the grain dump (format=dump)");
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  std::vector<Vec3> centres;
  centres.reserve(n * per);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d R = s.orientation[i].normalized().toRotationMatrix() * (i < s.scale.size() ? s.scale[i] : 1.0);
    for (const Vec3& o : grain.offsets()) {
      centres.push_back(s.position[i] + R * o);
      lo = lo.cwiseMin(centres.back()), hi = hi.cwiseMax(centres.back());
    }
  }
  if (centres.empty()) lo = hi = Vec3::Zero();
  std::string out = "ITEM: TIMESTEP\n" + std::to_string(s.step) + "\nITEM: NUMBER OF ATOMS\n" +
                    std::to_string(centres.size()) + "\nITEM: BOX BOUNDS ff ff ff\n";
  for (int k = 0; k < 3; ++k) out += number(lo[k]) + " " + number(hi[k]) + "\n";
  // mol: the grain's id in the grain dump, the grain's id + 1 (LAMMPS' molecule 0 is no molecule). A field the
  // stored snapshot predates has no column (no "nan").
  const bool d2min = s.d2min.size() == n, misorientation = s.misorientation.size() == n;
  out += "ITEM: ATOMS id mol type x y z radius penetration_ratio gamma_max equivalent_strain";
  out += std::string(d2min ? " d2min" : "") + (misorientation ? " misorientation" : "") + "\n";
  out.reserve(out.size() + centres.size() * 110);
  char line[320];
  for (std::size_t i = 0; i < n; ++i) {
    const double radius = grain.radius() * (i < s.scale.size() ? s.scale[i] : 1.0);
    char fields[64] = "";
    int at = 0;
    if (d2min) at += std::snprintf(fields + at, sizeof fields - at, " %.6g", s.d2min[i]);
    if (misorientation) at += std::snprintf(fields + at, sizeof fields - at, " %.6g", s.misorientation[i]);
    for (std::size_t k = 0; k < per; ++k) {
      const Vec3& x = centres[i * per + k];
      std::snprintf(line, sizeof line, "%zu %llu 1 %.9g %.9g %.9g %.6g %.6g %.6g %.6g%s\n", i * per + k + 1,
                    static_cast<unsigned long long>(value(s.id[i])) + 1, x.x(), x.y(), x.z(), radius,
                    s.penetration_ratio[i], s.gamma_max[i], s.equivalent_strain[i], fields);
      out += line;
    }
  }
  return out;
}

std::string snapshot_meshes_vtk(const GrainSnapshot& s) {
  const std::size_t n = s.id.size();
  // The paper's snapshots stored before the cell was kept: a = neighbour distance x sqrt2 (FCC).
  const double a = s.grain_size > 0 ? s.grain_size : std::sqrt(2.0) * neighbour_distance(s);
  const Polyhedron solid = Polyhedron::make(s.grain_shape, a > 0 ? a : 1.0);
  // A cell per face: a triangle or quadrilateral as itself, a larger face (the truncated octahedron's hexagons) as
  // the fan of triangles from its first corner. Each cell carries its grain's values.
  std::size_t per_grain_points = 0, per_grain_list = 0;
  std::vector<std::vector<std::size_t>> grain_cells;  // one grain's cells, its points counted from 0
  for (const Face& f : solid.faces()) {
    const std::size_t k = f.vertices.size(), first = per_grain_points;
    if (k <= 4) {
      grain_cells.emplace_back();
      for (std::size_t v = 0; v < k; ++v) grain_cells.back().push_back(first + v);
    } else {
      for (std::size_t v = 1; v + 1 < k; ++v) grain_cells.push_back({first, first + v, first + v + 1});
    }
    per_grain_points += k;
  }
  for (const auto& c : grain_cells) per_grain_list += c.size() + 1;
  const std::size_t cells_per_grain = grain_cells.size();  // each with its grain's values
  std::string out = "# vtk DataFile Version 3.0\ngranulab grain shapes, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " + std::to_string(n * per_grain_points) + " double\n";
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d R = s.orientation[i].normalized().toRotationMatrix();
    const double scale = i < s.scale.size() ? s.scale[i] : 1.0;
    for (const Face& f : solid.faces())
      for (const Vec3& v : f.vertices) {
        const Vec3 x = s.position[i] + R * (scale * v);
        out += number(x.x()) + " " + number(x.y()) + " " + number(x.z()) + "\n";
      }
  }
  std::string cells;
  std::vector<VtkCell> types;
  types.reserve(n * cells_per_grain);
  for (std::size_t i = 0; i < n; ++i)
    for (const auto& c : grain_cells) {
      cells += std::to_string(c.size());
      for (std::size_t p : c) cells += " " + std::to_string(p + i * per_grain_points);
      cells += "\n";
      types.push_back(c.size() == 3 ? VtkCell::triangle : VtkCell::quad);
    }
  append_cells(out, n * per_grain_list, cells, types);
  // Each face carries its grain's values (ParaView colours the grain by them): `id` the active scalars, the
  // others in a FIELD block, which every legacy reader reads (api/legacy_vtk.h).
  out += "CELL_DATA " + std::to_string(n * cells_per_grain) + "\nSCALARS id int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t f = 0; f < cells_per_grain; ++f) out += std::to_string(value(s.id[i])) + "\n";
  VtkFieldBlock fields;
  const auto scalars = [&](const char* name, const std::vector<double>& v) {
    if (v.size() != n) return;  // a field the stored snapshot predates
    std::string text;
    for (std::size_t i = 0; i < n; ++i) {
      const std::string line = number(v[i], "%.6g") + "\n";
      for (std::size_t f = 0; f < cells_per_grain; ++f) text += line;
    }
    fields.add(name, 1, n * cells_per_grain, std::move(text));
  };
  // `displacement` is the grain's displacement vector (m), as in the grain file and the JSON: one meaning per name.
  if (s.displacement.size() == n) {
    std::string text;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& d = s.displacement[i];
      const std::string line = number(d.x(), "%.6g") + " " + number(d.y(), "%.6g") + " " + number(d.z(), "%.6g") + "\n";
      for (std::size_t f = 0; f < cells_per_grain; ++f) text += line;
    }
    fields.add("displacement", 3, n * cells_per_grain, std::move(text));
  }
  scalars("penetration_ratio", s.penetration_ratio);
  scalars("gamma_max", s.gamma_max);
  scalars("equivalent_strain", s.equivalent_strain);
  scalars("d2min", s.d2min);
  scalars("misorientation", s.misorientation);
  fields.append_to(out, "grain_fields");
  return out;
}

}  // namespace granulab::api
