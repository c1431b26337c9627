#include "api/pictures/curve_pictures.h"

#include "api/job_status.h"

#include <cmath>

#include "api/pictures/colour_map.h"
#include "api/pictures/svg_text.h"

namespace granulab::pictures {

namespace {

using nlohmann::json;

std::vector<double> column(const json& curve, const char* name, double scale = 1) {
  std::vector<double> v;
  if (!curve.is_object() || !curve.contains(name) || !curve[name].is_array()) return v;
  v.reserve(curve[name].size());
  for (const json& x : curve[name]) v.push_back(x.is_number() ? x.get<double>() * scale : NAN);
  return v;
}

double number_at(const json& j, std::initializer_list<const char*> path, double fallback) {
  const json* at = &j;
  for (const char* key : path) {
    if (!at->is_object() || !at->contains(key)) return fallback;
    at = &(*at)[key];
  }
  return at->is_number() ? at->get<double>() : fallback;
}

bool has(const json& curve, const char* name) { return curve.is_object() && curve.contains(name); }

std::string title_of(const json& spec, const std::string& fallback) {
  const std::string label = spec.is_object() && spec.contains("label") && spec["label"].is_string()
                                ? spec["label"].get<std::string>() : "";
  return label.empty() ? fallback : label;
}

// The curve a sweep overlays, and its axes, for one job.
struct MainCurve {
  std::vector<double> x, y;
  std::string x_label, y_label;
};

MainCurve main_curve(const json& curve) {
  if (has(curve, "deviator"))
    return {column(curve, "strain", 100), column(curve, "deviator", 1e-3), "axial strain (%)", "deviator stress (kPa)"};
  if (has(curve, "tangential_over_p0"))
    return {column(curve, "slide_over_size"), column(curve, "tangential_over_p0"), "slide u / l (-)", "T / P0 (-)"};
  MainCurve c;
  const json names = curve.is_object() && curve.contains("columns") ? curve["columns"] : json::array();
  if (names.size() >= 2) {
    c.x = column(curve, names[0].get<std::string>().c_str());
    c.y = column(curve, names[1].get<std::string>().c_str());
    c.x_label = names[0].get<std::string>();
    c.y_label = names[1].get<std::string>();
  }
  return c;
}

}  // namespace

LinePlot job_curve_plot(const json& spec, const json& curve, const json& summary) {
  LinePlot plot;
  const std::string experiment = spec.value("experiment", std::string());
  plot.title = title_of(spec, experiment);
  if (has(curve, "deviator")) {
    plot.x_label = "axial strain (%)";
    plot.y_label = "stress (kPa)";
    const std::vector<double> strain = column(curve, "strain", 100);
    plot.series.push_back({"deviator", strain, column(curve, "deviator", 1e-3), palette(0), false});
    plot.series.push_back({"top platen", strain, column(curve, "stress_top", 1e-3), palette(1), false});
    plot.series.push_back({"bottom platen", strain, column(curve, "stress_bottom", 1e-3), palette(2), false});
    const double p0 = number_at(spec, {"loading", "confining_pressure"}, 0);
    if (p0 > 0) plot.note = "p0 = " + num(p0 * 1e-3, 4) + " kPa; platen stresses include p0";
    if (summary.is_object() && summary.contains("first_yield")) {
      const double e = number_at(summary, {"first_yield", "strain"}, NAN), s = number_at(summary, {"first_yield", "deviator"}, NAN);
      const double r = number_at(summary, {"first_yield", "deviator_over_p0"}, NAN);
      if (std::isfinite(e) && std::isfinite(s) && s > 0)
        plot.markers.push_back({e * 100, s * 1e-3, "first yield " + num(r, 3) + " p0"});
    }
  } else if (has(curve, "tangential_over_p0")) {
    plot.x_label = "slide u / l (-)";
    plot.y_label = "force / P0 (-)";
    const std::vector<double> u = column(curve, "slide_over_size");
    plot.series.push_back({"P / P0", u, column(curve, "normal_over_p0"), palette(0), false});
    plot.series.push_back({"T / P0", u, column(curve, "tangential_over_p0"), palette(1), false});
    // Eq. 1 of the paper: P/P0 = 1 - u/l, T/P0 = f (1 - u/l), up to the largest slide drawn.
    const double f = number_at(spec, {"material", "friction"}, 0);
    double end = number_at(spec, {"loading", "max_slide"}, 1);
    Series p{"P / P0, eq. 1", {0, end}, {1, 1 - end}, palette(0), true};
    Series t{"T / P0, eq. 1 (f = " + num(f, 3) + ")", {0, end}, {f, f * (1 - end)}, palette(1), true};
    plot.series.push_back(p);
    plot.series.push_back(t);
  } else {
    // Unknown experiment: every stress column against the first column.
    const json names = curve.is_object() && curve.contains("columns") ? curve["columns"] : json::array();
    if (!names.empty()) {
      const std::string x = names[0].get<std::string>();
      plot.x_label = x;
      plot.y_label = "stress (kPa)";
      for (std::size_t k = 1; k < names.size(); ++k) {
        const std::string name = names[k].get<std::string>();
        if (name.find("stress") == std::string::npos) continue;
        plot.series.push_back({name, column(curve, x.c_str()), column(curve, name.c_str(), 1e-3), "", false});
      }
    }
  }
  return plot;
}

LinePlot sweep_curves_plot(const std::string& title, const std::vector<SweepCurve>& jobs, std::size_t left_out) {
  LinePlot plot;
  plot.title = title;
  if (left_out) plot.note = std::to_string(left_out) + " more jobs not drawn";
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    MainCurve c = main_curve(jobs[i].curve);
    if (plot.x_label.empty()) plot.x_label = c.x_label, plot.y_label = c.y_label;
    std::string label;
    if (jobs[i].values.is_object())
      for (const auto& [key, value] : jobs[i].values.items()) {
        const auto dot = key.rfind('.');
        label += (label.empty() ? "" : ", ") + key.substr(dot == std::string::npos ? 0 : dot + 1) + " = " +
                 (value.is_number() ? num(value.get<double>(), 6) : value.dump());
      }
    if (jobs[i].status != api::status_name(api::JobStatus::succeeded)) label += " (" + jobs[i].status + ")";
    // Up to eight curves take the palette's distinct colours; more run along the colour map in sweep order.
    const std::string colour = jobs.size() <= 8 ? palette(i) : viridis(double(i) / double(jobs.size() - 1));
    plot.series.push_back({label, std::move(c.x), std::move(c.y), colour, false});
  }
  return plot;
}

}  // namespace granulab::pictures
