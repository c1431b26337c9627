#include "api/dic_files.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "api/legacy_vtk.h"
#include "engine/analysis/snapshot_layers.h"

namespace granulab::api {

namespace {

std::string number(double v) {
  if (std::isnan(v)) return "nan";
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

}  // namespace

double default_dic_step(const GrainSnapshot& s) {
  const double d = neighbour_distance(s);
  return d > 0 ? 0.5 * d : 0.5 * s.grain_size;
}

DicMap snapshot_dic_map(const GrainSnapshot& s, std::optional<double> step, std::size_t max_nodes) {
  const double h = step.value_or(default_dic_step(s));
  if (!(h > 0) || !std::isfinite(h)) throw std::invalid_argument("'step' must be a positive grid step in m");
  try {
    return dic_map(s, h, 0, max_nodes);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("'step': ") + e.what());
  }
}

std::string dic_csv(const DicMap& m) {
  std::string out = "x,z,ux,uy,uz,exx,ezz,exz,gamma_max\n";
  for (int k = 0; k < m.nz; ++k)
    for (int i = 0; i < m.nx; ++i) {
      const std::size_t n = std::size_t(k) * m.nx + i;
      out += number(m.x0 + i * m.step) + "," + number(m.z0 + k * m.step);
      for (const auto* f : {&m.ux, &m.uy, &m.uz, &m.exx, &m.ezz, &m.exz, &m.gamma_max}) out += "," + number((*f)[n]);
      out += "\n";
    }
  return out;
}

std::string dic_vtk(const DicMap& m) {
  const std::size_t nodes = std::size_t(m.nx) * std::size_t(m.nz);
  // No "nan": VTK's legacy reader stops at the first one, keeps the arrays read so far (the one it stopped in
  // half read) and reports success. A node off the face has `measured` 0 and 0 in every field, as the title says.
  const auto measured = [&](std::size_t n) { return std::isfinite(m.exx[n]); };
  const auto value = [&](const std::vector<double>& field, std::size_t n) {
    return measured(n) && std::isfinite(field[n]) ? number(field[n]) : std::string("0");
  };
  std::string out =
      "# vtk DataFile Version 3.0\ngranulab DIC-like map of the front face (reference coordinates, m); "
      "nodes off the face have measured 0 and 0 in every field\nASCII\nDATASET STRUCTURED_POINTS\n";
  out += "DIMENSIONS " + std::to_string(m.nx) + " 1 " + std::to_string(m.nz) + "\n";
  out += "ORIGIN " + number(m.x0) + " " + number(m.y) + " " + number(m.z0) + "\n";
  out += "SPACING " + number(m.step) + " " + number(m.step) + " " + number(m.step) + "\n";
  out += "POINT_DATA " + std::to_string(nodes) + "\n";
  // VTK's x runs fastest, then y (one node), then z: the map's own node order.
  out += "SCALARS measured int 1\nLOOKUP_TABLE default\n";
  for (std::size_t n = 0; n < nodes; ++n) out += measured(n) ? "1\n" : "0\n";
  out += "VECTORS displacement double\n";
  for (std::size_t n = 0; n < nodes; ++n) out += value(m.ux, n) + " " + value(m.uy, n) + " " + value(m.uz, n) + "\n";
  VtkFieldBlock strains;
  const std::pair<const char*, const std::vector<double>*> scalars[] = {
      {"exx", &m.exx}, {"ezz", &m.ezz}, {"exz", &m.exz}, {"gamma_max", &m.gamma_max}};
  for (const auto& [name, field] : scalars) {
    std::string text;
    for (std::size_t n = 0; n < nodes; ++n) text += value(*field, n) + "\n";
    strains.add(name, 1, nodes, std::move(text));
  }
  strains.append_to(out, "strains");
  return out;
}

}  // namespace granulab::api
