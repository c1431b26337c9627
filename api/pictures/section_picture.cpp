#include "api/pictures/section_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include "api/pictures/colour_map.h"
#include "api/snapshot_files.h"
#include "api/pictures/svg_text.h"
#include "engine/analysis/slip_bands.h"
#include "engine/analysis/snapshot_layers.h"
#include "engine/geometry/polyhedron.h"

namespace granulab::pictures {

namespace {

struct FieldInfo {
  const char* name;
  const char* label;  // colour bar caption, with unit
  double scale;       // stored value -> shown value
};

FieldInfo info(Field f) {
  switch (f) {
    case Field::penetration_ratio: return {"penetration_ratio", "contact penetration Δ/Δ̄ (-)", 1};
    case Field::gamma_max: return {"gamma_max", "max shear strain γmax (-)", 1};
    case Field::equivalent_strain: return {"equivalent_strain", "equivalent strain (-)", 1};
    case Field::displacement: return {"displacement", "displacement (mm)", 1e3};
    case Field::d2min: return {"d2min", "non-affine D²min / l² (-)", 1};
    case Field::misorientation: return {"misorientation", "misorientation (°)", 1};
  }
  return {"", "", 1};
}

double field_value(const GrainSnapshot& s, Field f, std::size_t i) {
  switch (f) {
    case Field::penetration_ratio: return s.penetration_ratio[i];
    case Field::gamma_max: return s.gamma_max[i];
    case Field::equivalent_strain: return s.equivalent_strain[i];
    case Field::displacement: return s.displacement[i].norm();
    // Over the squared neighbour distance l (taken where the picture starts): comparable across grain sizes.
    case Field::d2min: return i < s.d2min.size() ? s.d2min[i] : std::nan("");
    case Field::misorientation: return i < s.misorientation.size() ? s.misorientation[i] : std::nan("");
  }
  return 0;
}

// Lattice measures from the reference state (snapshot_layers.h).
struct Layers {
  double neighbour = 0;    // nearest-neighbour distance (m)
  std::vector<int> layer;  // per grain
  int count = 0;
};

Layers find_layers(const GrainSnapshot& s) {
  Layers out;
  out.neighbour = neighbour_distance(s);
  if (!(out.neighbour > 0)) out.neighbour = 1;
  SnapshotLayers layers = snapshot_layers(s);
  out.layer = std::move(layers.layer);
  out.count = layers.count;
  return out;
}

// The rhombic dodecahedron of cubic cell a in its body frame: six 4-fold vertices (a/2 on each axis), eight 3-fold
// ones (a/4, a/4, a/4), and 24 edges joining each 3-fold vertex to the three 4-fold ones on its side.
std::vector<std::array<Vec3, 2>> dodecahedron_edges(double a) {
  std::vector<std::array<Vec3, 2>> edges;
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1}) {
        const Vec3 corner = 0.25 * a * Vec3(sx, sy, sz);
        edges.push_back({corner, Vec3(0.5 * a * sx, 0, 0)});
        edges.push_back({corner, Vec3(0, 0.5 * a * sy, 0)});
        edges.push_back({corner, Vec3(0, 0, 0.5 * a * sz)});
      }
  return edges;
}

// Any other grain's edges in its body frame, each once: the solid's face boundaries.
std::vector<std::array<Vec3, 2>> grain_edges(Shape shape, double size) {
  std::vector<std::array<Vec3, 2>> edges;
  const Polyhedron solid = Polyhedron::make(shape, size);
  const double tol = 1e-9 * size;
  for (const Face& f : solid.faces())
    for (std::size_t k = 0; k < f.vertices.size(); ++k) {
      const Vec3 &p = f.vertices[k], &q = f.vertices[(k + 1) % f.vertices.size()];
      const bool seen = std::any_of(edges.begin(), edges.end(), [&](const std::array<Vec3, 2>& e) {
        return ((e[0] - q).norm() < tol && (e[1] - p).norm() < tol) || ((e[0] - p).norm() < tol && (e[1] - q).norm() < tol);
      });
      if (!seen) edges.push_back({p, q});
    }
  return edges;
}

// The cross-section of grain i by the plane y = its centre's y, as (x, z) points in order around it.
std::vector<std::array<double, 2>> cross_section(const std::vector<std::array<Vec3, 2>>& edges, const Vec3& centre,
                                                 const Quat& q) {
  std::vector<std::array<double, 2>> points;
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  for (const auto& e : edges) {
    const Vec3 p = R * e[0], r = R * e[1];  // relative to the centre; the plane is y = 0 here
    if ((p.y() < 0) == (r.y() < 0) || p.y() == r.y()) continue;
    const Vec3 x = p + (r - p) * (p.y() / (p.y() - r.y()));
    const std::array<double, 2> point{centre.x() + x.x(), centre.z() + x.z()};
    // A vertex on the plane is met by several of its edges: keep it once.
    if (std::none_of(points.begin(), points.end(), [&](const std::array<double, 2>& o) {
          return std::abs(o[0] - point[0]) + std::abs(o[1] - point[1]) < 1e-9 * (std::abs(point[0]) + std::abs(point[1]) + 1e-6);
        }))
      points.push_back(point);
  }
  if (points.size() < 3) return {};
  double cx = 0, cz = 0;
  for (const auto& p : points) cx += p[0], cz += p[1];
  cx /= points.size(), cz /= points.size();
  std::sort(points.begin(), points.end(), [&](const auto& u, const auto& v) {
    return std::atan2(u[1] - cz, u[0] - cx) < std::atan2(v[1] - cz, v[0] - cx);
  });
  return points;
}

}  // namespace

std::optional<Field> parse_field(const std::string& name) {
  for (Field f : {Field::penetration_ratio, Field::gamma_max, Field::equivalent_strain, Field::displacement, Field::d2min,
                 Field::misorientation})
    if (name == info(f).name) return f;
  return std::nullopt;
}

int layer_count(const GrainSnapshot& s) { return find_layers(s).count; }

std::string section_svg(const GrainSnapshot& s, Field field, std::optional<int> layer, const std::string& title) {
  const Layers layers = find_layers(s);
  const int chosen = layer.value_or(std::max(0, (layers.count - 1) / 2));
  if (chosen < 0 || chosen >= std::max(1, layers.count))
    throw std::out_of_range("'slice' must be a " + s.layer_planes + " layer from 0 (the front face) to " +
                            std::to_string(std::max(0, layers.count - 1)) + ", got " + std::to_string(chosen));
  FieldInfo fi = info(field);
  if (field == Field::d2min) fi.scale = 1 / (layers.neighbour * layers.neighbour);
  if ((field == Field::d2min && s.d2min.size() != s.id.size()) ||
      (field == Field::misorientation && s.misorientation.size() != s.id.size()))
    throw std::invalid_argument(std::string("this snapshot has no '") + fi.name +
                                "': it was stored before that field existed");
  // The paper's grains keep the cell measured from the neighbour distance, as their pictures always had it.
  const bool paper = s.grain_shape == Shape::rhombic_dodecahedron;
  const double a = paper || !(s.grain_size > 0) ? layers.neighbour * std::sqrt(2.0) : s.grain_size;
  const auto edges = paper ? dodecahedron_edges(a) : grain_edges(s.grain_shape, a);

  std::vector<std::size_t> grains;
  for (std::size_t i = 0; i < s.id.size(); ++i)
    if (layers.layer[i] == chosen) grains.push_back(i);
  std::vector<std::vector<std::array<double, 2>>> shapes;
  double x0 = 1e300, x1 = -1e300, z0 = 1e300, z1 = -1e300, lo = 1e300, hi = -1e300;
  for (std::size_t i : grains) {
    shapes.push_back(cross_section(edges, s.position[i], s.orientation[i]));
    for (const auto& p : shapes.back())
      x0 = std::min(x0, p[0]), x1 = std::max(x1, p[0]), z0 = std::min(z0, p[1]), z1 = std::max(z1, p[1]);
    const double v = field_value(s, field, i) * fi.scale;
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  if (!(x1 > x0) || !(z1 > z0)) x0 = 0, x1 = 1, z0 = 0, z1 = 1;
  if (!(hi >= lo)) lo = 0, hi = 1;
  if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) hi = lo + (lo == 0 ? 1 : 0.01 * std::abs(lo));

  // Page: the section scaled to 600 px tall (or 560 wide), a colour bar on its right.
  const double scale = std::min(600 / (z1 - z0), 560 / (x1 - x0));
  const double margin = 20, top = 60, pw = (x1 - x0) * scale, ph = (z1 - z0) * scale;
  // Wide enough for the title (about 8.5 px per character of 15 px bold text), up to 1,200 px; tall enough for
  // the colour bar (a wide, flat layer is short).
  const std::string caption = "axial strain " + num(100 * s.strain, 3) + " %, " + s.layer_planes + " layer " +
                              std::to_string(chosen) + " of 0-" + std::to_string(std::max(0, layers.count - 1)) +
                              ", " + std::to_string(grains.size()) + " grains; compression axis vertical";
  // Wide enough for the caption too (about 6.5 px per character of 12 px text).
  const double text_width = std::max(8.5 * double(title.size()), 6.5 * double(caption.size())) + 40;
  const double bar_x = margin + pw + 30,
               W = std::min(std::max(bar_x + 130, text_width), std::max(bar_x + 130, 1200.0));
  const double H = top + std::max(ph, 220.0) + 40;
  const auto X = [&](double x) { return margin + (x - x0) * scale; };
  const auto Z = [&](double z) { return top + (z1 - z) * scale; };  // z (compression axis) up

  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    num(W) + "\" height=\"" + num(H) + "\" viewBox=\"0 0 " + num(W) + " " + num(H) +
                    "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
                    "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<text x=\"" + num(W / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" +
         xml_escape(fit_text(title, W - 20, 8.5)) + "</text>\n";
  svg += "<text x=\"" + num(W / 2) + "\" y=\"42\" text-anchor=\"middle\" fill=\"#555\">" + xml_escape(caption) +
         "</text>\n";
  svg += "<g class=\"grains\" stroke=\"#222\" stroke-width=\"0.6\">\n";
  for (std::size_t k = 0; k < grains.size(); ++k) {
    if (shapes[k].empty()) continue;
    const double v = field_value(s, field, grains[k]) * fi.scale;
    std::string points;
    for (const auto& p : shapes[k]) points += num(X(p[0]), 6) + "," + num(Z(p[1]), 6) + " ";
    svg += "<polygon class=\"grain\" data-id=\"" + std::to_string(value(s.id[grains[k]])) + "\" data-value=\"" +
           num(v, 6) + "\" fill=\"" + viridis((v - lo) / (hi - lo)) + "\" points=\"" + points + "\"/>\n";
  }
  svg += "</g>\n";

  // Interfaces within the layer sliding more than twice the mean (over all interfaces), as the trace of
  // the shared face: through the midpoint, across the branch, one hexagon edge (neighbour / sqrt3) long.
  double mean = 0;
  for (double x : s.sliding) mean += std::abs(x);
  mean = s.sliding.empty() ? 0 : mean / s.sliding.size();
  std::unordered_map<std::uint32_t, std::size_t> index;
  for (std::size_t i : grains) index[value(s.id[i])] = i;
  std::size_t sliding = 0;
  svg += "<g class=\"sliding\" stroke=\"black\" stroke-width=\"2.2\" stroke-linecap=\"round\">\n";
  for (std::size_t k = 0; k < s.interfaces.size() && k < s.sliding.size(); ++k) {
    // The floor (1e-3 of the grain spacing) keeps round-off from drawing lines on an undeformed crystal.
    if (std::abs(s.sliding[k]) <= std::max(2 * mean, 1e-3 * layers.neighbour)) continue;
    const auto a_it = index.find(value(s.interfaces[k].a)), b_it = index.find(value(s.interfaces[k].b));
    if (a_it == index.end() || b_it == index.end()) continue;
    const Vec3 &pa = s.position[a_it->second], &pb = s.position[b_it->second];
    const double mx = 0.5 * (pa.x() + pb.x()), mz = 0.5 * (pa.z() + pb.z());
    double bx = pb.x() - pa.x(), bz = pb.z() - pa.z();
    const double length = std::hypot(bx, bz);
    if (!(length > 0)) continue;
    bx /= length, bz /= length;
    const double h = 0.5 * layers.neighbour / std::sqrt(3.0);
    svg += "<line x1=\"" + num(X(mx - h * bz), 6) + "\" y1=\"" + num(Z(mz + h * bx), 6) + "\" x2=\"" +
           num(X(mx + h * bz), 6) + "\" y2=\"" + num(Z(mz - h * bx), 6) + "\"/>\n";
    ++sliding;
  }
  svg += "</g>\n";

  // The snapshot's slip bands (slip_bands.h) where they cut this layer: the trace of each fitted plane on the layer's
  // mid-plane (reference positions), dashed, with its lattice plane's indices. A band nearly parallel to the layer
  // has no trace here.
  double layer_y = 0;
  for (std::size_t i : grains) layer_y += s.position[i].y() - s.displacement[i].y();
  layer_y = grains.empty() ? 0 : layer_y / double(grains.size());
  svg += "<g class=\"slip-bands\" stroke=\"#d62728\" stroke-width=\"1.8\" stroke-dasharray=\"7,4\" fill=\"#d62728\">\n";
  for (const SlipBand& band : s.slip_bands) {
    const double nx = band.normal[0], ny = band.normal[1], nz = band.normal[2], in = std::hypot(nx, nz);
    if (in < 0.2) continue;
    const double c = band.offset - ny * layer_y;
    const double px = c * nx / (in * in), pz = c * nz / (in * in), dx = -nz / in, dz = nx / in;
    double t0 = -1e300, t1 = 1e300;
    for (const auto& [p, d, lo_edge, hi_edge] : {std::array<double, 4>{px, dx, x0, x1}, std::array<double, 4>{pz, dz, z0, z1}}) {
      if (std::abs(d) < 1e-12) {
        if (p < lo_edge || p > hi_edge) t0 = 1, t1 = 0;
        continue;
      }
      const double a = (lo_edge - p) / d, b = (hi_edge - p) / d;
      t0 = std::max(t0, std::min(a, b)), t1 = std::min(t1, std::max(a, b));
    }
    if (!(t1 > t0)) continue;
    svg += "<line class=\"slip-band\" x1=\"" + num(X(px + t0 * dx), 6) + "\" y1=\"" + num(Z(pz + t0 * dz), 6) +
           "\" x2=\"" + num(X(px + t1 * dx), 6) + "\" y2=\"" + num(Z(pz + t1 * dz), 6) + "\"/>\n";
    svg += "<text stroke=\"none\" x=\"" + num(X(px + t1 * dx) + 4, 6) + "\" y=\"" + num(Z(pz + t1 * dz) - 4, 6) + "\">" +
           xml_escape(band_plane_text(band, snapshot_lattice(s))) + "</text>\n";
  }
  svg += "</g>\n";

  const double bar_top = top + 10, bar_h = std::min(std::max(ph, 220.0) - 20, 360.0);
  svg += colour_bar_svg(bar_x, bar_top, bar_h, lo, hi, fi.label);
  svg += "<text x=\"" + num(bar_x) + "\" y=\"" + num(bar_top + bar_h + 28) + "\" font-size=\"11\">" +
         std::to_string(sliding) + " interfaces</text><text x=\"" + num(bar_x) + "\" y=\"" + num(bar_top + bar_h + 42) +
         "\" font-size=\"11\">sliding &gt; 2x mean</text>\n";
  return svg + "</svg>\n";
}

}  // namespace granulab::pictures
