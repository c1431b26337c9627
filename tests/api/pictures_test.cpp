// The server's pictures: the section of a crystal snapshot is the lattice's own geometry (one hexagon of
// the {111} layer's Voronoi area per grain, turned with the grain), only interfaces sliding beyond the
// threshold are drawn, axes get 1-2-5 ticks, any text is escaped into well-formed XML, and snapshots
// survive the JSON round trip the server stores them through.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "api/pictures/curve_pictures.h"
#include "api/pictures/line_plot.h"
#include "api/pictures/section_picture.h"
#include "api/pictures/svg_text.h"
#include "engine/analysis/snapshot_layers.h"
#include "api/snapshot_files.h"
#include "engine/crystal/crystal_lattice.h"

namespace granulab::pictures {
namespace {

constexpr double kSize = 0.01;  // a (m)

// The reference state of a 4 x 6 x 3 crystal (no pre-strain): every grain at its site, turned like the
// lattice, with its 12-neighbour interfaces; fields set to the grain index so colours can be traced.
GrainSnapshot reference_crystal(int grains_x = 4, int rows_z = 6, int layers_y = 3) {
  CrystalGeometry g;
  g.size = kSize;
  g.grains_x = grains_x, g.rows_z = rows_z, g.layers_y = layers_y;
  const CrystalLattice lattice = build_crystal(g);
  GrainSnapshot s;
  for (const LatticeSite& site : lattice.sites) {
    s.id.push_back(site.id);
    s.position.push_back(site.position);
    s.displacement.push_back(Vec3::Zero());
    s.orientation.push_back(lattice.orientation);
    const double v = double(s.id.size());
    s.penetration.push_back(v), s.penetration_ratio.push_back(v), s.gamma_max.push_back(v),
        s.equivalent_strain.push_back(v);
  }
  const double d = kSize / std::sqrt(2.0);
  for (std::size_t i = 0; i < s.id.size(); ++i)
    for (std::size_t j = i + 1; j < s.id.size(); ++j)
      if ((s.position[i] - s.position[j]).norm() < 1.1 * d)
        s.interfaces.push_back({s.id[i], s.id[j]}), s.sliding.push_back(0);
  return s;
}

struct Polygon {
  std::vector<std::array<double, 2>> points;
  double area() const {
    double a = 0;
    for (std::size_t k = 0; k < points.size(); ++k) {
      const auto &p = points[k], &q = points[(k + 1) % points.size()];
      a += p[0] * q[1] - q[0] * p[1];
    }
    return std::abs(a) / 2;
  }
};

std::vector<Polygon> grains_of(const std::string& svg) {
  std::vector<Polygon> out;
  static const std::regex polygon(R"re(<polygon class="grain"[^>]* points="([^"]*)")re");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), polygon); it != std::sregex_iterator(); ++it) {
    Polygon p;
    std::istringstream in((*it)[1].str());
    double x, y;
    char comma;
    while (in >> x >> comma >> y) p.points.push_back({x, y});
    out.push_back(p);
  }
  return out;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

Vec3 centroid(const Polygon& p) {
  Vec3 c = Vec3::Zero();
  for (const auto& v : p.points) c += Vec3(v[0], v[1], 0) / double(p.points.size());
  return c;
}

TEST(SectionPicture, EveryGrainOfTheLayerIsAHexagonOfTheLayersVoronoiArea) {
  const GrainSnapshot s = reference_crystal();
  ASSERT_EQ(layer_count(s), 3);
  for (int layer : {0, 1, 2}) {
    const std::vector<Polygon> grains = grains_of(section_svg(s, Field::penetration_ratio, layer, "t"));
    ASSERT_EQ(grains.size(), 24u) << "layer " << layer;  // 4 x 6 grains per {111} layer
    // The in-layer neighbour distance in pixels, from the hexagons' centres; the Voronoi cell of a
    // triangular lattice of spacing d has area sqrt(3)/2 d^2, so each hexagon has exactly that area:
    // the sections tile the layer without gaps or overlaps.
    double d = 1e300;
    for (std::size_t i = 0; i < grains.size(); ++i)
      for (std::size_t j = i + 1; j < grains.size(); ++j)
        d = std::min(d, (centroid(grains[i]) - centroid(grains[j])).norm());
    for (const Polygon& p : grains) {
      EXPECT_EQ(p.points.size(), 6u);
      EXPECT_NEAR(p.area(), std::sqrt(3.0) / 2 * d * d, 1e-4 * d * d);  // coordinates have 6 significant digits
    }
  }
}

TEST(SectionPicture, AGrainTurnedAboutTheLayerNormalIsDrawnTurned) {
  GrainSnapshot s = reference_crystal();
  const std::string before = section_svg(s, Field::penetration_ratio, 1, "t");
  // Turn every grain of the crystal by 30 degrees about lab y (the {111} normal): the hexagons turn by 30
  // degrees, which (for a hexagon) moves each vertex to the middle of an old edge: areas unchanged,
  // vertex angles shifted by 30 degrees.
  const Quat turn(Eigen::AngleAxisd(M_PI / 6, Vec3::UnitY()));
  for (Quat& q : s.orientation) q = turn * q;
  const auto a = grains_of(before), b = grains_of(section_svg(s, Field::penetration_ratio, 1, "t"));
  ASSERT_EQ(a.size(), b.size());
  auto angles = [](const Polygon& p) {
    double cx = 0, cy = 0;
    for (const auto& v : p.points) cx += v[0] / p.points.size(), cy += v[1] / p.points.size();
    std::vector<double> out;
    for (const auto& v : p.points) out.push_back(std::fmod(std::atan2(v[1] - cy, v[0] - cx) + 2 * M_PI, M_PI / 3));
    return out;
  };
  // The picture's scale follows the turned hexagons' bounding box: compare areas in units of the (unmoved)
  // centre spacing.
  const auto spacing = [](const std::vector<Polygon>& g) {
    double d = 1e300;
    for (std::size_t j = 1; j < g.size(); ++j) d = std::min(d, (centroid(g[0]) - centroid(g[j])).norm());
    return d;
  };
  EXPECT_NEAR(b[0].area() / std::pow(spacing(b), 2), a[0].area() / std::pow(spacing(a), 2), 1e-4);
  const double shift = std::fmod(angles(b[0])[0] - angles(a[0])[0] + 2 * M_PI, M_PI / 3);
  EXPECT_NEAR(shift, M_PI / 6, 1e-3);
}

TEST(SectionPicture, OnlyInterfacesOfTheLayerSlidingOverTwiceTheMeanAreDrawn) {
  GrainSnapshot s = reference_crystal();
  const double d = kSize / std::sqrt(2.0);
  const auto lines = [&](int layer) {
    const std::string svg = section_svg(s, Field::penetration_ratio, layer, "t");
    const auto begin = svg.find("<g class=\"sliding\""), end = svg.find("</g>", begin);
    return count(svg.substr(begin, end - begin), "<line");
  };
  EXPECT_EQ(lines(1), 0u);  // nothing slid
  // Every interface slides 0.01 d (above the 1e-3 d floor); two of layer 1 and one across layers 1-2 slide d.
  for (double& x : s.sliding) x = 0.01 * d;
  const auto layer_of = [&](GrainId id) {
    for (std::size_t i = 0; i < s.id.size(); ++i)
      if (s.id[i] == id) return int(std::lround((s.position[i].y() - s.position[0].y()) / (d * std::sqrt(2.0 / 3.0))));
    return -1;
  };
  int in_layer = 0, across = 0;
  for (std::size_t k = 0; k < s.interfaces.size(); ++k) {
    const int la = layer_of(s.interfaces[k].a), lb = layer_of(s.interfaces[k].b);
    if (la == 1 && lb == 1 && in_layer < 2) s.sliding[k] = d, ++in_layer;
    if (la != lb && across < 1) s.sliding[k] = -d, ++across;
  }
  ASSERT_EQ(in_layer, 2);
  EXPECT_EQ(lines(1), 2u);
  // Uniform sliding: nothing is more than twice the mean.
  for (double& x : s.sliding) x = 0.05 * d;
  EXPECT_EQ(lines(1), 0u);
}

// A slip band (slip_bands.h) is drawn where its plane cuts the layer, labelled with its indices; a band parallel to
// the layer has no trace there. A field the snapshot predates (d2min, misorientation) is refused, not drawn as zero.
TEST(SectionPicture, SlipBandsAreDrawnAsTheirTracesOnTheLayer) {
  GrainSnapshot s = reference_crystal();
  SlipBand inclined;
  inclined.plane[0] = inclined.plane[1] = inclined.plane[2] = 1;
  inclined.normal[0] = std::sqrt(0.5), inclined.normal[2] = std::sqrt(0.5);
  inclined.offset = 0;  // through the sample centre
  SlipBand parallel;
  parallel.normal[1] = 1;
  s.slip_bands = {inclined, parallel};
  const std::string svg = section_svg(s, Field::penetration_ratio, 1, "t");
  EXPECT_EQ(count(svg, "<line class=\"slip-band\""), 1u);
  EXPECT_NE(svg.find(">(1 1 1)</text>"), std::string::npos);
  s.slip_bands.clear();
  EXPECT_EQ(count(section_svg(s, Field::penetration_ratio, 1, "t"), "<line class=\"slip-band\""), 0u);
  EXPECT_THROW(section_svg(s, Field::d2min, 1, "t"), std::invalid_argument);
  EXPECT_THROW(section_svg(s, Field::misorientation, 1, "t"), std::invalid_argument);
  s.d2min.assign(s.id.size(), 1e-10);
  EXPECT_NE(section_svg(s, Field::d2min, 1, "t").find("D²min"), std::string::npos);
}

TEST(SectionPicture, AWideFlatLayerStillHasItsColourBarAndALongTitleIsCut) {
  const GrainSnapshot s = reference_crystal(60, 1, 3);
  ASSERT_EQ(layer_count(s), 3);
  const std::string svg = section_svg(s, Field::penetration_ratio, 1, std::string(100000, 'x'));
  EXPECT_EQ(svg.find("height=\"-"), std::string::npos) << "a negative height";
  const auto width = std::stod(svg.substr(svg.find("width=\"") + 7));
  EXPECT_LE(width, 1200.0);
  EXPECT_LT(svg.size(), 100000u);  // the title was cut
}

TEST(SectionPicture, ASliceOutsideTheCrystalNamesTheValidLayers) {
  const GrainSnapshot s = reference_crystal();
  try {
    section_svg(s, Field::gamma_max, 3, "t");
    FAIL() << "slice 3 of 3 layers accepted";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("0 (the front face) to 2"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(parse_field("displacement"));
  EXPECT_FALSE(parse_field("Displacement"));
  EXPECT_FALSE(parse_field(""));
}

TEST(Ticks, AreOneTwoOrFiveTimesAPowerOfTenAndCoverTheRange) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-8, 8), unit(-1, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(rng));
    double lo = unit(rng) * scale, hi = lo + std::abs(unit(rng)) * scale + 1e-3 * scale;
    const std::vector<double> t = nice_ticks(lo, hi);
    ASSERT_GE(t.size(), 2u) << lo << " " << hi;
    ASSERT_LE(t.size(), 13u) << lo << " " << hi;
    const double step = t[1] - t[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 || std::abs(mantissa - 5) < 1e-6 ||
                std::abs(mantissa - 10) < 1e-6)
        << step;
    EXPECT_GE(t.front(), lo - 1e-9 * step);
    EXPECT_LT(t.front() - step, lo);  // no tick missing at the start
    EXPECT_LE(t.back(), hi + 1e-9 * step);
    EXPECT_GT(t.back() + step, hi);  // nor at the end
  }
}

TEST(SvgText, EscapesMarkupAndDropsWhatXmlCannotHold) {
  EXPECT_EQ(xml_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&apos;");
  EXPECT_EQ(xml_escape("p\xc3\xa9tanque"), "p\xc3\xa9tanque");  // UTF-8 kept
  EXPECT_EQ(xml_escape("bad\xff\xc3 byte\x01"), "bad byte");    // stray bytes and controls dropped
  EXPECT_EQ(xml_escape("a\xef\xbf\xbf\xef\xbf\xbe\xed\xa0\x80"
                       "b\xef\xbf\xbd"),
            "ab\xef\xbf\xbd");  // U+FFFF, U+FFFE, a surrogate: not XML
  EXPECT_EQ(num(NAN), "0");
  EXPECT_EQ(num(1.23456789, 3), "1.23");
}

// A crystal's stick-slip events (its headline's `events`) are ticks along the top of its curve, at their strains.
TEST(CurvePicture, MarksTheRunsEventsAtTheirStrains) {
  const nlohmann::json spec = {{"experiment", "crystal_compression"}};
  nlohmann::json curve = {{"columns", {"strain", "stress_top", "stress_bottom", "deviator"}},
                          {"strain", {0.0, 0.01, 0.02}},
                          {"stress_top", {6e4, 3e5, 3.2e5}},
                          {"stress_bottom", {6e4, 3e5, 3.2e5}},
                          {"deviator", {0.0, 2.4e5, 2.6e5}}};
  const nlohmann::json summary = {{"stress_drops", {{"events", {{{"strain", 0.005}}, {{"strain", 0.015}}}}}}};
  const LinePlot plot = job_curve_plot(spec, curve, summary, CurveChoice{});
  ASSERT_EQ(plot.events.size(), 2u);
  EXPECT_DOUBLE_EQ(plot.events[0], 0.5);  // in % of strain, as the axis
  EXPECT_DOUBLE_EQ(plot.events[1], 1.5);
  EXPECT_EQ(plot.events_label, "stress drops (2)");
  const std::string svg = line_plot_svg(plot);
  EXPECT_EQ(count(svg, "class=\"event\""), 2u);
  EXPECT_NE(svg.find("stress drops (2)"), std::string::npos);
  // Without a summary (a running job) there is nothing to mark.
  EXPECT_TRUE(job_curve_plot(spec, curve, nlohmann::json::object(), CurveChoice{}).events.empty());
}

TEST(LinePlot, ThinsLongSeriesButKeepsTheLatestPointAndSkipsNaN) {
  LinePlot plot;
  Series s{"s", {}, {}, "", false};
  for (int i = 0; i < 5001; ++i) s.x.push_back(i), s.y.push_back(i == 10 ? NAN : std::sin(i));
  plot.series.push_back(s);
  const std::string svg = line_plot_svg(plot);
  const auto begin = svg.find("points=\"", svg.find("class=\"series\"")) + 8;
  const std::string points = svg.substr(begin, svg.find('"', begin) - begin);
  const std::size_t n = count(points, ",");
  EXPECT_LE(n, 2001u);
  EXPECT_GE(n, 1000u);
  EXPECT_EQ(points.find("nan"), std::string::npos);
  // The last point is at the right end of the x axis (5000 is a tick, so it ends the axis).
  const std::string last = points.substr(points.rfind(' ', points.size() - 2) + 1);
  const double x_last = std::stod(last);
  double x_max = 0;
  std::istringstream in(points);
  for (double x, y; in >> x && in.ignore(1) && in >> y;) x_max = std::max(x_max, x);
  EXPECT_EQ(x_last, x_max);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
  EXPECT_NE(line_plot_svg(LinePlot{}).find("</svg>"), std::string::npos);  // nothing to draw is still a picture
}

// The width estimate is never narrower than the text as Chromium draws it in DejaVu Sans at 12 px (measured with
// getComputedTextLength(): 183.3, 425.6, 209.7, 76.4 and 174.9 px).
TEST(SvgText, TheWidthEstimateCoversTheDrawnText) {
  const std::vector<std::pair<std::string, double>> drawn = {
      {"friction = 0.1, max_slide = 0.2", 183.3},
      {"confining_pressure = 30000, friction = 0.35, edge_spheres = 4 (failed)", 425.6},
      {"ABCDEFGHIJKLMNOPQRSTUVWXYZ", 209.7},
      {"0123456789", 76.4},
      {"first yield 5.96 p0 at 0.512 %", 174.9}};
  for (const auto& [text, px] : drawn) {
    EXPECT_GE(text_width(text, 12), px - 0.5) << text;
    EXPECT_LE(text_width(text, 12), 1.01 * px) << text;  // and not much wider: rounding up only
  }
  EXPECT_NEAR(text_width("p\xc3\xa9", 10), 6.4 + 10, 1e-12);  // beyond ASCII, a whole em each
  // Wrapping breaks after spaces, each line within the width, and loses nothing but spaces at the breaks.
  const std::string label = "confining_pressure = 30000, friction = 0.35, edge_spheres = 4 (failed)";
  const std::vector<std::string> lines = wrap_text(label, 200, 12);
  ASSERT_GE(lines.size(), 3u);
  std::string joined;
  for (const std::string& l : lines) {
    EXPECT_LE(text_width(l, 12), 200) << l;
    joined += (joined.empty() ? "" : " ") + l;
  }
  EXPECT_EQ(joined, label);
  // A list of "key = value" pairs breaks between pairs where it can.
  EXPECT_EQ(wrap_text("rate_number = 0.000123456, damping = 0.0512345, friction = 0.123456", 320, 12),
            (std::vector<std::string>{"rate_number = 0.000123456,", "damping = 0.0512345, friction = 0.123456"}));
  EXPECT_EQ(wrap_text("short", 200, 12), std::vector<std::string>{"short"});
  EXPECT_EQ(wrap_text("", 200, 12), std::vector<std::string>{""});
  const std::vector<std::string> cut = wrap_text(std::string(100, 'W'), 120, 12);  // one word, wider than a line
  ASSERT_EQ(cut.size(), 1u);
  EXPECT_LE(text_width(cut[0], 12), 120);
  EXPECT_EQ(cut[0].substr(cut[0].size() - 3), "\u2026");
}

// Every line of the legend's text ends inside the picture, however long a sweep's labels are (issue 51: a 930 px
// picture's legend began at 614 px and its labels ran off the right edge).
TEST(LinePlot, TheLegendFitsInThePictureForLongSweepLabels) {
  for (const std::size_t varied : {1, 3, 6}) {
    std::vector<SweepCurve> jobs;
    for (int j = 0; j < 4; ++j) {
      SweepCurve c;
      c.spec = {{"experiment", "two_cube_sliding"}};
      c.curve = {{"columns", {"slide", "tangential_force"}}, {"slide", {0.0, 1e-4}}, {"tangential_force", {0.0, 1.0}}};
      c.status = j == 3 ? "failed" : "succeeded";
      for (std::size_t k = 0; k < varied; ++k)
        c.values["section.a_rather_long_field_name_" + std::to_string(k)] = 123456.789 * (j + 1);
      jobs.push_back(c);
    }
    const std::string svg = line_plot_svg(sweep_curves_plot("a sweep", jobs, 0));
    std::smatch m;
    ASSERT_TRUE(std::regex_search(svg, m, std::regex("<svg [^>]*width=\"([0-9.]+)\"")));
    const double width = std::stod(m[1]);
    const std::string legend = svg.substr(svg.find("<g class=\"legend\">"));
    std::size_t lines = 0;
    const std::regex text(R"re(<(?:text|tspan) x="([0-9.]+)"[^>]*>([^<]+)<)re");
    for (auto it = std::sregex_iterator(legend.begin(), legend.end(), text); it != std::sregex_iterator(); ++it) {
      const std::string shown = (*it)[2];
      if (shown.size() <= 1) continue;  // a marker's number
      ++lines;
      EXPECT_LE(std::stod((*it)[1]) + text_width(shown, 12), width) << varied << " values: " << shown;
    }
    EXPECT_GE(lines, 4u) << svg;
    EXPECT_LE(width, 760 + 200) << "the picture grows by the legend's width at most";
    if (varied == 6) EXPECT_NE(legend.find("<tspan"), std::string::npos) << "six values wrap";
  }
}

TEST(SnapshotFiles, JsonRoundTripAndTheDumpsRadiusIsHalfTheNeighbourDistance) {
  GrainSnapshot s = reference_crystal();
  s.strain = 0.01, s.step = 1234;
  s.displacement[3] = Vec3(1e-4, -2e-4, 3e-4);
  s.sliding[5] = 7e-5;
  const GrainSnapshot r = api::snapshot_from_json(api::snapshot_json(s));
  EXPECT_EQ(api::snapshot_json(r), api::snapshot_json(s));
  EXPECT_EQ(r.step, 1234u);
  EXPECT_NEAR(neighbour_distance(s), kSize / std::sqrt(2.0), 1e-12);
  const std::string dump = api::snapshot_lammps_dump(s);
  EXPECT_NE(dump.find("ITEM: ATOMS id type x y z radius "), std::string::npos);
  const auto line = dump.find('\n', dump.find("ITEM: ATOMS")) + 1;
  std::istringstream first(dump.substr(line));
  double id, type, x, y, z, radius;
  first >> id >> type >> x >> y >> z >> radius;
  EXPECT_NEAR(radius, kSize / std::sqrt(8.0), 1e-6 * kSize);  // written with 6 significant digits
  EXPECT_THROW(api::snapshot_from_json(nlohmann::json::object()), std::invalid_argument);
  nlohmann::json short_one = api::snapshot_json(s);
  short_one["grains"]["qz"].erase(0);
  EXPECT_THROW(api::snapshot_from_json(short_one), std::invalid_argument);
  // The fields of issue 28 survive it too: D^2_min, the misorientation, the crystal's frame and the slip bands.
  s.grain_size = kSize;
  s.crystal_orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  s.d2min.assign(s.id.size(), 2e-11);
  s.misorientation.assign(s.id.size(), 0.5);
  s.misorientation_axis.assign(s.id.size(), Vec3(0, 0.6, 0.8));
  SlipBand band;
  band.plane[0] = -2, band.plane[1] = 1, band.plane[2] = 1;
  band.slip = 3e-4, band.dilation_angle = 12, band.interfaces = 40, band.normal[2] = 1;
  band.direction[0] = 1, band.direction[1] = 1, band.direction[2] = 1;
  s.slip_bands = {band};
  const GrainSnapshot t = api::snapshot_from_json(api::snapshot_json(s));
  EXPECT_EQ(api::snapshot_json(t), api::snapshot_json(s));
  ASSERT_EQ(t.slip_bands.size(), 1u);
  EXPECT_EQ(t.slip_bands[0].plane[0], -2);
  EXPECT_EQ(t.slip_bands[0].interfaces, 40u);
  EXPECT_NEAR(t.crystal_orientation.angularDistance(s.crystal_orientation), 0, 1e-12);
  EXPECT_EQ(api::snapshot_json(s)["slip_bands"][0]["plane"], "(-2 1 1)");
  EXPECT_NE(api::snapshot_lammps_dump(t).find(" d2min misorientation "), std::string::npos);
}

}  // namespace
}  // namespace granulab::pictures
