#include "api/snapshot_files.h"

#include "engine/analysis/snapshot_layers.h"

#include "api/dic_files.h"
#include "api/legacy_vtk.h"
#include "api/network_files.h"
#include "api/summary_json.h"
#include "engine/analysis/slip_bands.h"
#include "engine/crystal/crystal_lattice.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
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

nlohmann::json slip_bands_json(const std::vector<SlipBand>& bands, LatticeType lattice) {
  // The engine names the fields (write_slip_bands), as it does in job summaries.
  JsonSummaryWriter w;
  write_slip_bands(w, bands, lattice);
  return w.document()["slip_bands"];
}

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
  grains["gamma_max"] = s.gamma_max;
  grains["equivalent_strain"] = s.equivalent_strain;
  if (s.d2min.size() == n) grains["d2min"] = s.d2min;
  if (s.misorientation.size() == n && s.misorientation_axis.size() == n) {
    grains["misorientation"] = s.misorientation;
    for (int k = 0; k < 3; ++k) {
      const char* axis[] = {"misorientation_axis_x", "misorientation_axis_y", "misorientation_axis_z"};
      grains[axis[k]] = column(n, [&](std::size_t i) { return s.misorientation_axis[i][k]; });
    }
  }
  if (s.scale.size() == n) grains["scale"] = s.scale;
  // Grain indices as JSON integers (readers that keep JSON's types, pandas among them, get integer columns).
  const auto indices = [](std::size_t m, auto grain_of) {
    std::vector<std::uint32_t> v(m);
    for (std::size_t i = 0; i < m; ++i) v[i] = value(grain_of(i));
    return v;
  };
  nlohmann::json interfaces;
  interfaces["a"] = indices(s.interfaces.size(), [&](std::size_t i) { return s.interfaces[i].a; });
  interfaces["b"] = indices(s.interfaces.size(), [&](std::size_t i) { return s.interfaces[i].b; });
  interfaces["sliding"] = s.sliding;
  nlohmann::json out = {{"strain", s.strain}, {"step", s.step}, {"grains", grains}, {"interfaces", interfaces}};
  if (!s.contacts.empty()) {
    const std::size_t m = s.contacts.size();
    nlohmann::json c;
    c["a"] = indices(m, [&](std::size_t i) { return s.contacts[i].a; });
    c["b"] = indices(m, [&](std::size_t i) { return s.contacts[i].b; });
    for (int k = 0; k < 3; ++k) {
      const char* axis[] = {"fx", "fy", "fz"};
      c[axis[k]] = column(m, [&](std::size_t i) { return s.contact_force[i][k]; });
    }
    out["contact_network"] = c;
  }
  if (s.grain_size > 0) {
    const Quat& q = s.crystal_orientation;
    out["crystal"] = {{"grain", to_string(s.grain_shape)},
                      {"size", s.grain_size},
                      {"layer_spacing", s.layer_spacing},
                      {"layer_planes", s.layer_planes},
                      {"edge_spheres", s.edge_spheres},
                      {"sphere_overlap", s.sphere_overlap},
                      {"orientation", {q.w(), q.x(), q.y(), q.z()}}};
  }
  out["slip_bands"] = slip_bands_json(s.slip_bands, snapshot_lattice(s));
  return out;
}

namespace {

std::vector<double> numbers(const nlohmann::json& group, const char* key, std::size_t n) {
  if (!group.contains(key) || !group[key].is_array() || group[key].size() != n)
    throw std::invalid_argument(std::string("snapshot: '") + key + "' is missing or has the wrong length");
  std::vector<double> v;
  v.reserve(n);
  for (const auto& x : group[key]) {
    if (!x.is_number()) throw std::invalid_argument(std::string("snapshot: '") + key + "' holds a non-number");
    v.push_back(x.get<double>());
  }
  return v;
}

}  // namespace

GrainSnapshot snapshot_from_json(const nlohmann::json& j) {
  if (!j.is_object() || !j.contains("grains") || !j["grains"].is_object() || !j["grains"].contains("id") ||
      !j["grains"]["id"].is_array())
    throw std::invalid_argument("snapshot: no grains");
  const auto& g = j["grains"];
  const std::size_t n = g["id"].size();
  GrainSnapshot s;
  s.strain = j.value("strain", 0.0);
  s.step = j.value("step", std::uint64_t(0));
  // The crystal's description; snapshots stored before lattices were a choice have none (the paper's crystal).
  if (j.contains("crystal") && j["crystal"].is_object()) {
    const auto& c = j["crystal"];
    if (c.contains("grain") && c["grain"].is_string() && !shape_from_string(c["grain"].get<std::string>(), s.grain_shape))
      throw std::invalid_argument("snapshot: 'crystal.grain' names no grain shape");
    if (c.contains("size") && c["size"].is_number()) s.grain_size = c["size"].get<double>();
    if (c.contains("layer_spacing") && c["layer_spacing"].is_number()) s.layer_spacing = c["layer_spacing"].get<double>();
    if (c.contains("layer_planes") && c["layer_planes"].is_string()) s.layer_planes = c["layer_planes"].get<std::string>();
    // The clump, within the spec's own ranges (grain.edge_spheres, grain.overlap); anything else counts as not kept.
    if (c.contains("edge_spheres") && c["edge_spheres"].is_number_integer() && c.contains("sphere_overlap") &&
        c["sphere_overlap"].is_number()) {
      const auto ne = c["edge_spheres"].get<long long>();
      const double kappa = c["sphere_overlap"].get<double>();
      if (ne >= 2 && ne <= 40 && kappa >= 0 && kappa <= 0.95) s.edge_spheres = int(ne), s.sphere_overlap = kappa;
    }
  }
  // The crystal's frame; snapshots stored before slip bands had none: the paper's crystal.
  const nlohmann::json* q = j.contains("crystal") && j["crystal"].is_object() && j["crystal"].contains("orientation")
                                ? &j["crystal"]["orientation"]
                                : nullptr;
  if (q && q->is_array() && q->size() == 4 && std::all_of(q->begin(), q->end(), [](const auto& x) { return x.is_number(); }))
    s.crystal_orientation = Quat((*q)[0].get<double>(), (*q)[1].get<double>(), (*q)[2].get<double>(), (*q)[3].get<double>());
  else if (s.grain_shape == Shape::rhombic_dodecahedron)
    s.crystal_orientation = off_axis_orientation();
  if (j.contains("slip_bands") && j["slip_bands"].is_array())
    for (const auto& b : j["slip_bands"]) {
      if (!b.is_object()) continue;
      const auto number = [&](const char* key) { return b.contains(key) && b[key].is_number() ? b[key].get<double>() : 0.0; };
      const auto triple = [&](const char* key, auto* into) {
        if (b.contains(key) && b[key].is_array() && b[key].size() == 3)
          for (int k = 0; k < 3; ++k)
            if (b[key][k].is_number()) into[k] = b[key][k].get<std::remove_pointer_t<decltype(into)>>();
      };
      s.slip_bands.push_back(read_slip_band(number, triple));
    }
  for (double id : numbers(g, "id", n)) s.id.push_back(GrainId(std::uint32_t(id)));
  const auto x = numbers(g, "x", n), y = numbers(g, "y", n), z = numbers(g, "z", n);
  const auto dx = numbers(g, "dx", n), dy = numbers(g, "dy", n), dz = numbers(g, "dz", n);
  const auto qw = numbers(g, "qw", n), qx = numbers(g, "qx", n), qy = numbers(g, "qy", n), qz = numbers(g, "qz", n);
  for (std::size_t i = 0; i < n; ++i) {
    s.position.emplace_back(x[i], y[i], z[i]);
    s.displacement.emplace_back(dx[i], dy[i], dz[i]);
    s.orientation.emplace_back(qw[i], qx[i], qy[i], qz[i]);
  }
  s.penetration = numbers(g, "penetration", n);
  s.penetration_ratio = numbers(g, "penetration_ratio", n);
  // Stored before the field had one name everywhere: "max_shear_strain".
  s.gamma_max = numbers(g, g.contains("gamma_max") ? "gamma_max" : "max_shear_strain", n);
  s.equivalent_strain = numbers(g, "equivalent_strain", n);
  // Snapshots stored before D^2_min and the misorientation existed have neither: they stay empty.
  if (g.contains("d2min")) s.d2min = numbers(g, "d2min", n);
  if (g.contains("misorientation")) {
    s.misorientation = numbers(g, "misorientation", n);
    const auto ax = numbers(g, "misorientation_axis_x", n), ay = numbers(g, "misorientation_axis_y", n),
               az = numbers(g, "misorientation_axis_z", n);
    for (std::size_t i = 0; i < n; ++i) s.misorientation_axis.emplace_back(ax[i], ay[i], az[i]);
  }
  if (g.contains("scale")) s.scale = numbers(g, "scale", n);
  const nlohmann::json empty = nlohmann::json::object();
  // The contact network; snapshots stored before it was kept have none.
  const auto& c = j.contains("contact_network") && j["contact_network"].is_object() ? j["contact_network"] : empty;
  if (const std::size_t m = c.contains("a") && c["a"].is_array() ? c["a"].size() : 0) {
    const auto a = numbers(c, "a", m), b = numbers(c, "b", m);
    const auto fx = numbers(c, "fx", m), fy = numbers(c, "fy", m), fz = numbers(c, "fz", m);
    for (std::size_t k = 0; k < m; ++k) {
      s.contacts.push_back({GrainId(std::uint32_t(a[k])), GrainId(std::uint32_t(b[k]))});
      s.contact_force.emplace_back(fx[k], fy[k], fz[k]);
    }
  }
  const auto& f = j.contains("interfaces") && j["interfaces"].is_object() ? j["interfaces"] : empty;
  const std::size_t m = f.contains("a") && f["a"].is_array() ? f["a"].size() : 0;
  if (m) {
    const auto a = numbers(f, "a", m), b = numbers(f, "b", m);
    for (std::size_t k = 0; k < m; ++k)
      s.interfaces.push_back({GrainId(std::uint32_t(a[k])), GrainId(std::uint32_t(b[k]))});
    s.sliding = numbers(f, "sliding", m);
  }
  return s;
}

std::string snapshot_lammps_dump(const GrainSnapshot& s) {
  const std::size_t n = s.id.size();
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& x : s.position) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  if (s.position.empty()) lo = hi = Vec3::Zero();
  std::string out = "ITEM: TIMESTEP\n" + std::to_string(s.step) + "\nITEM: NUMBER OF ATOMS\n" + std::to_string(n) +
                    "\nITEM: BOX BOUNDS ff ff ff\n";
  for (int k = 0; k < 3; ++k) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.9g %.9g\n", lo[k], hi[k]);
    out += buf;
  }
  // As LAMMPS writes a dump: ids from 1 (the grain's id + 1) and a type (1: every grain is the same kind; knocked-out
  // grains are not in the snapshot), which readers such as ASE's require. A field the stored snapshot predates has
  // no column (no "nan").
  const bool d2min = s.d2min.size() == n,
             misorientation = s.misorientation.size() == n && s.misorientation_axis.size() == n;
  // radius: the grain's inscribed sphere (half the neighbour distance), so OVITO draws touching grains.
  const double radius = 0.5 * neighbour_distance(s);
  out +=
      "ITEM: ATOMS id type x y z radius dx dy dz quatw quati quatj quatk penetration penetration_ratio gamma_max "
      "equivalent_strain";
  if (d2min) out += " d2min";
  if (misorientation) out += " misorientation misorientation_axis_x misorientation_axis_y misorientation_axis_z";
  out += "\n";
  char line[640];
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 &x = s.position[i], &d = s.displacement[i];
    const Quat& q = s.orientation[i];
    int at = std::snprintf(
        line, sizeof line, "%llu 1 %.9g %.9g %.9g %.6g %.6g %.6g %.6g %.9g %.9g %.9g %.9g %.6g %.6g %.6g %.6g",
        static_cast<unsigned long long>(value(s.id[i])) + 1, x.x(), x.y(), x.z(), radius, d.x(), d.y(), d.z(), q.w(),
        q.x(), q.y(), q.z(), s.penetration[i], s.penetration_ratio[i], s.gamma_max[i], s.equivalent_strain[i]);
    if (d2min) at += std::snprintf(line + at, sizeof line - at, " %.6g", s.d2min[i]);
    if (misorientation) {
      const Vec3& axis = s.misorientation_axis[i];
      at += std::snprintf(line + at, sizeof line - at, " %.6g %.6g %.6g %.6g", s.misorientation[i], axis.x(), axis.y(),
                          axis.z());
    }
    out += line;
    out += "\n";
  }
  return out;
}

std::string snapshot_grains_vtk(const GrainSnapshot& s) {
  const std::size_t n = s.id.size();
  std::string out = "# vtk DataFile Version 3.0\ngranulab grains, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& x : s.position) append(out, "%.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  std::string vertices;
  for (std::size_t i = 0; i < n; ++i) vertices += "1 " + std::to_string(i) + "\n";
  append_cells(out, n, 2 * n, vertices, VtkCell::vertex);
  out += "POINT_DATA " + std::to_string(n) + "\nSCALARS id int 1\nLOOKUP_TABLE default\n";
  for (GrainId id : s.id) out += std::to_string(value(id)) + "\n";
  out += "VECTORS displacement double\n";
  for (const Vec3& d : s.displacement) append(out, "%.6g %.6g %.6g\n", d.x(), d.y(), d.z());
  // The other arrays in a FIELD block, which every legacy reader reads (api/legacy_vtk.h).
  VtkFieldBlock fields;
  auto scalars = [&](const char* name, const std::vector<double>& v) {
    std::string text;
    char buf[40];
    for (double x : v) std::snprintf(buf, sizeof buf, "%.6g\n", x), text += buf;
    fields.add(name, 1, n, std::move(text));
  };
  scalars("penetration", s.penetration);
  scalars("penetration_ratio", s.penetration_ratio);
  scalars("gamma_max", s.gamma_max);
  scalars("equivalent_strain", s.equivalent_strain);
  if (s.d2min.size() == n) scalars("d2min", s.d2min);
  if (s.misorientation.size() == n && s.misorientation_axis.size() == n) {
    scalars("misorientation", s.misorientation);
    std::string axes;
    for (const Vec3& a : s.misorientation_axis) append(axes, "%.6g %.6g %.6g\n", a.x(), a.y(), a.z());
    fields.add("misorientation_axis", 3, n, std::move(axes));
  }
  std::string quaternions;
  char buf[128];
  for (const Quat& q : s.orientation)
    std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g\n", q.w(), q.x(), q.y(), q.z()), quaternions += buf;
  fields.add("quaternion_wxyz", 4, n, std::move(quaternions));
  fields.append_to(out, "grain_fields");
  return out;
}

std::string snapshot_interfaces_vtk(const GrainSnapshot& s) {
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i = 0; i < s.id.size(); ++i) index[value(s.id[i])] = i;
  const std::size_t n = s.id.size(), m = s.interfaces.size();
  std::string out = "# vtk DataFile Version 3.0\ngranulab interfaces, strain " + std::to_string(s.strain) +
                    "\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " + std::to_string(n) + " double\n";
  for (const Vec3& x : s.position) append(out, "%.9g %.9g %.9g\n", x.x(), x.y(), x.z());
  std::string lines;
  for (const auto& [a, b] : s.interfaces)
    lines += "2 " + std::to_string(index[value(a)]) + " " + std::to_string(index[value(b)]) + "\n";
  append_cells(out, m, 3 * m, lines, VtkCell::line);
  out += "CELL_DATA " + std::to_string(m) + "\nSCALARS sliding double 1\nLOOKUP_TABLE default\n";
  char buf[40];
  for (double x : s.sliding) std::snprintf(buf, sizeof buf, "%.6g\n", x), out += buf;
  return out;
}


std::vector<SnapshotFile> snapshot_files(std::size_t k, const GrainSnapshot& s) {
  const std::string stem = "snapshots/snapshot_" + std::to_string(k);
  std::vector<SnapshotFile> files = {{stem + ".json", snapshot_json(s).dump() + "\n"},
                                     {stem + ".dump", snapshot_lammps_dump(s)},
                                     {stem + "_grains.vtk", snapshot_grains_vtk(s)},
                                     {stem + "_interfaces.vtk", snapshot_interfaces_vtk(s)},
                                     {stem + "_contacts.vtk", snapshot_contacts_vtk(s)},
                                     {stem + "_contacts.dump", snapshot_contacts_dump(s)},
                                     {stem + "_meshes.vtk", snapshot_meshes_vtk(s)}};
  // The front face's DIC-like map at its default step (about four nodes per face grain); none without grains.
  // (A stored snapshot without a neighbour distance or grain size has no default step: no map then.)
  try {
    const DicMap map = snapshot_dic_map(s, std::nullopt, 4000000);
    files.push_back({stem + "_dic.csv", dic_csv(map)});
    files.push_back({stem + "_dic.vtk", dic_vtk(map)});
  } catch (const std::invalid_argument&) {
  }
  return files;
}

}  // namespace granulab::api
