#include "api/pictures/dic_picture.h"

#include <algorithm>
#include <cmath>

#include "api/pictures/colour_map.h"
#include "api/pictures/svg_text.h"

namespace granulab::pictures {

namespace {

struct DicInfo {
  const char* name;
  const char* label;  // colour bar caption, with unit
  double scale;       // stored -> shown
};

DicInfo info(DicField f) {
  switch (f) {
    case DicField::gamma_max: return {"gamma_max", "max shear strain γmax (-)", 1};
    case DicField::exx: return {"exx", "strain Exx (-)", 1};
    case DicField::ezz: return {"ezz", "axial strain Ezz (-)", 1};
    case DicField::exz: return {"exz", "shear strain Exz (-)", 1};
    case DicField::ux: return {"ux", "displacement ux (mm)", 1e3};
    case DicField::uz: return {"uz", "displacement uz (mm)", 1e3};
  }
  return {"", "", 1};
}

const std::vector<double>& values(const DicMap& m, DicField f) {
  switch (f) {
    case DicField::gamma_max: return m.gamma_max;
    case DicField::exx: return m.exx;
    case DicField::ezz: return m.ezz;
    case DicField::exz: return m.exz;
    case DicField::ux: return m.ux;
    case DicField::uz: return m.uz;
  }
  return m.gamma_max;
}

}  // namespace

std::optional<DicField> parse_dic_field(const std::string& name) {
  for (DicField f : {DicField::gamma_max, DicField::exx, DicField::ezz, DicField::exz, DicField::ux, DicField::uz})
    if (name == info(f).name) return f;
  return std::nullopt;
}

std::string dic_svg(const DicMap& m, DicField field, double strain, const std::string& title) {
  const DicInfo fi = info(field);
  const std::vector<double>& v = values(m, field);
  double lo = 1e300, hi = -1e300;
  std::size_t measured = 0;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x * fi.scale), hi = std::max(hi, x * fi.scale), ++measured;
  if (!(hi >= lo)) lo = 0, hi = 1;
  if (hi - lo < 1e-12 * std::max(1.0, std::abs(hi))) hi = lo + (lo == 0 ? 1 : 0.01 * std::abs(lo));

  // Page: the map scaled to 600 px tall (or 560 wide), the colour bar on its right.
  const double width = m.nx * m.step, height = m.nz * m.step;
  const double scale = std::min(600 / height, 560 / width);
  const double margin = 20, top = 60, pw = width * scale, ph = height * scale, cell = m.step * scale;
  const std::string caption = "front face at strain " + num(100 * strain, 3) + " %; grid step " +
                              num(m.step * 1e3, 3) + " mm, subset radius " + num(m.subset * 1e3, 3) + " mm, " +
                              std::to_string(m.nx) + " x " + std::to_string(m.nz) + " nodes, " +
                              std::to_string(m.grains) + " grains; compression axis vertical";
  const double text_width = std::max(8.5 * double(title.size()), 6.5 * double(caption.size())) + 40;
  const double bar_x = margin + pw + 30, W = std::min(std::max(bar_x + 130, text_width), std::max(bar_x + 130, 1200.0));
  const double H = top + std::max(ph, 220.0) + 30;
  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
                    num(W) + "\" height=\"" + num(H) + "\" viewBox=\"0 0 " + num(W) + " " + num(H) +
                    "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
                    "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  svg += "<text x=\"" + num(W / 2) + "\" y=\"22\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" +
         xml_escape(fit_text(title, W - 20, 8.5)) + "</text>\n";
  svg += "<text x=\"" + num(W / 2) + "\" y=\"42\" text-anchor=\"middle\" fill=\"#555\">" +
         xml_escape(fit_text(caption, W - 20, 6.5)) + "</text>\n";
  // One square per node, centred on it (node k = 0 at the bottom: z up); slightly oversized so no seams show.
  svg += "<g class=\"dic-map\" shape-rendering=\"crispEdges\">\n";
  for (int k = 0; k < m.nz; ++k)
    for (int i = 0; i < m.nx; ++i) {
      const double x = v[std::size_t(k) * m.nx + i] * fi.scale;
      if (!std::isfinite(x)) continue;
      svg += "<rect x=\"" + num(margin + i * cell, 6) + "\" y=\"" + num(top + (m.nz - 1 - k) * cell, 6) +
             "\" width=\"" + num(cell + 0.3, 4) + "\" height=\"" + num(cell + 0.3, 4) + "\" fill=\"" +
             viridis((x - lo) / (hi - lo)) + "\"/>\n";
    }
  svg += "</g>\n";
  svg += "<rect class=\"frame\" x=\"" + num(margin) + "\" y=\"" + num(top) + "\" width=\"" + num(pw) + "\" height=\"" +
         num(ph) + "\" fill=\"none\" stroke=\"#999\" stroke-width=\"0.5\"/>\n";
  svg += colour_bar_svg(bar_x, top + 10, std::min(std::max(ph, 220.0) - 20, 360.0), lo, hi, fi.label);
  svg += "<text x=\"" + num(bar_x) + "\" y=\"" + num(top + std::min(std::max(ph, 220.0) - 20, 360.0) + 38) +
         "\" font-size=\"11\">" + std::to_string(measured) + " nodes measured</text>\n";
  return svg + "</svg>\n";
}

}  // namespace granulab::pictures
