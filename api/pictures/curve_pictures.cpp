#include "api/pictures/curve_pictures.h"

#include <cmath>

#include "api/headline_json.h"
#include "api/job_status.h"
#include "api/pictures/colour_map.h"
#include "api/pictures/svg_text.h"
#include "api/spec.h"
#include "engine/experiments/registry.h"

namespace granulab::pictures {

namespace {

using nlohmann::json;

std::vector<double> column(const json& curve, const std::string& name, double factor) {
  std::vector<double> v;
  if (!curve.is_object() || !curve.contains(name) || !curve[name].is_array()) return v;
  v.reserve(curve[name].size());
  for (const json& x : curve[name]) v.push_back(x.is_number() ? x.get<double>() * factor : NAN);
  return v;
}

std::string title_of(const json& spec, const std::string& fallback) {
  const std::string label =
      spec.is_object() && spec.contains("label") && spec["label"].is_string() ? spec["label"].get<std::string>() : "";
  return label.empty() ? fallback : label;
}

std::unique_ptr<Experiment> registered(const json& spec) {
  // A spec without "experiment" (or null) is of the first registered one, as parse_spec reads it.
  const bool named = spec.is_object() && spec.contains("experiment") && spec["experiment"].is_string();
  const ExperimentType* type =
      named ? find_experiment_type(spec["experiment"].get<std::string>()) : &experiment_types().front();
  return type ? type->make() : nullptr;
}

const CurveColumn* find_column(const std::vector<CurveColumn>& columns, const std::string& name) {
  for (const CurveColumn& c : columns)
    if (name == c.name) return &c;
  return nullptr;
}

// How the values of one axis read for this job: a factor on the stored values, and the axis label.
struct Reading {
  double factor = 1;
  std::string label;
};

Reading reading(const Axis& axis, Units units, const json& spec) {
  const Scale& scale = units == Units::natural ? axis.natural : axis.si;
  const auto divisor = api::scale_divisor(scale, spec);
  if (!divisor) return reading(axis, Units::si, spec);  // the spec lacks the field: SI still reads
  return {scale.factor / *divisor, std::string(axis.label) + " (" + scale.unit + ")"};
}

// The series drawn for the reader's choice, each as (legend, column, factor), and the y axis label.
struct Drawn {
  struct One {
    std::string label, column;
    double factor;
  };
  std::vector<One> series;
  std::string y_label;
};

Drawn drawn(const Headline& h, const json& spec, const CurveChoice& choice) {
  Drawn d;
  const Reading y = reading(h.y, choice.units, spec);
  d.y_label = y.label;
  if (choice.y.empty()) {
    for (const HeadlineSeries& s : h.series)
      d.series.push_back({s.label, choice.units == Units::si && s.si_column ? s.si_column : s.column,
                          choice.units == Units::si && s.si_column ? h.y.si.factor : y.factor});
    return d;
  }
  // One column: on the headline's y axis when it holds the same quantity, else as stored.
  const auto experiment = registered(spec);
  const std::vector<CurveColumn> none;
  const auto& columns = experiment ? experiment->curve_columns() : none;
  const CurveColumn* chosen = find_column(columns, choice.y);
  const CurveColumn* first = h.series.empty() ? nullptr : find_column(columns, h.series[0].column);
  if (chosen && first && std::string(chosen->unit) == first->unit) {
    d.series.push_back({choice.y, choice.y, y.factor});
  } else {
    d.series.push_back({choice.y, choice.y, 1});
    d.y_label = choice.y + (chosen ? " (" + std::string(chosen->unit) + ")" : "");
  }
  return d;
}

}  // namespace

Headline headline_for(const json& spec) {
  try {
    return api::parse_spec(spec).experiment->headline();
  } catch (const std::exception&) {
    // a spec this build no longer reads: its experiment's axes without the closed forms
  }
  if (const auto experiment = registered(spec)) {
    Headline h = experiment->headline();
    h.references.clear();
    return h;
  }
  return {};
}

std::vector<std::string> curve_column_names(const json& spec) {
  std::vector<std::string> names;
  if (const auto experiment = registered(spec))
    for (const CurveColumn& c : experiment->curve_columns()) names.push_back(c.name);
  return names;
}

LinePlot job_curve_plot(const json& spec, const json& curve, const json& summary, const CurveChoice& choice) {
  LinePlot plot;
  plot.title = title_of(spec, spec.is_object() ? spec.value("experiment", std::string()) : "");
  Headline h = headline_for(spec);
  if (!h.x_column) {
    // An experiment this build does not know: its second column against its first, as stored.
    const json names = curve.is_object() && curve.contains("columns") ? curve["columns"] : json::array();
    if (names.size() < 2) return plot;
    const std::string x = names[0].get<std::string>(), y = names[1].get<std::string>();
    plot.x_label = x, plot.y_label = y;
    plot.series.push_back({y, column(curve, x, 1), column(curve, y, 1), "", false});
    return plot;
  }
  const Reading x = reading(h.x, choice.units, spec);
  const Drawn d = drawn(h, spec, choice);
  plot.x_label = x.label, plot.y_label = d.y_label;
  const std::vector<double> xs = column(curve, h.x_column, x.factor);
  for (std::size_t k = 0; k < d.series.size(); ++k)
    plot.series.push_back(
        {d.series[k].label, xs, column(curve, d.series[k].column, d.series[k].factor), palette(k), false});
  if (choice.y.empty()) {
    for (const ReferenceCurve& r : h.references) {
      std::vector<double> rx, ry = choice.units == Units::si ? r.y_si : r.y_natural;
      for (double v : r.x) rx.push_back(v * x.factor);
      plot.series.push_back({r.label, rx, ry, palette(r.series), true});
    }
    if (h.note) plot.note = h.note;
  }
  // Key values: named in the legend; those that are points of the curve marked on it (when it is drawn).
  const double y_factor = d.series.empty() ? 1 : d.series[0].factor;
  const bool first_drawn = choice.y.empty() && !h.series.empty() && d.series[0].column == h.series[0].column;
  for (const KeyValue& v : h.values) {
    if (const auto reason = api::missing_reason(summary, v.status)) {  // named, never marked: there is no such point
      Marker m;
      m.label = std::string(v.label) + ": " + *reason;
      m.on_curve = false;
      plot.markers.push_back(m);
      continue;
    }
    const auto value = api::number_at_path(summary, v.key);
    if (!value) continue;
    Marker m;
    m.label =
        std::string(v.label) + " " + num(*value, 3) + (std::string(v.unit) == "-" ? "" : " " + std::string(v.unit));
    const auto at_x = v.at_x ? api::number_at_path(summary, v.at_x) : std::nullopt;
    const auto at_y = v.at_y ? api::number_at_path(summary, v.at_y) : std::nullopt;
    if (at_x) {
      const Scale& sx = choice.units == Units::natural ? h.x.natural : h.x.si;
      m.label += " at " + num(*at_x * x.factor, 3) + " " + sx.unit;
    }
    m.on_curve = at_x && at_y && first_drawn;
    if (m.on_curve) m.x = at_x.value_or(0) * x.factor, m.y = at_y.value_or(0) * y_factor;
    plot.markers.push_back(m);
  }
  // The run's events (a crystal's stick-slip drops) as ticks along the top, at their x.
  if (h.events.list) {
    const json* list = api::value_at_path(summary, h.events.list);
    if (list && list->is_array()) {
      for (const json& e : *list)
        if (e.is_object() && e.contains(h.events.x) && e[h.events.x].is_number())
          plot.events.push_back(e[h.events.x].get<double>() * x.factor);
      if (!plot.events.empty()) plot.events_label = std::string(h.events.label) + " (" + std::to_string(plot.events.size()) + ")";
    }
  }
  return plot;
}

LinePlot sweep_curves_plot(const std::string& title, const std::vector<SweepCurve>& jobs, std::size_t left_out,
                           const CurveChoice& choice) {
  LinePlot plot;
  plot.title = title;
  if (left_out) plot.note = std::to_string(left_out) + " more jobs not drawn";
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    const Headline h = headline_for(jobs[i].spec);
    std::vector<double> x, y;
    if (h.x_column) {
      const Reading rx = reading(h.x, choice.units, jobs[i].spec);
      Drawn d = drawn(h, jobs[i].spec, choice);
      if (plot.x_label.empty()) plot.x_label = rx.label, plot.y_label = d.y_label;
      x = column(jobs[i].curve, h.x_column, rx.factor);
      if (!d.series.empty()) y = column(jobs[i].curve, d.series[0].column, d.series[0].factor);
    }
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
    plot.series.push_back({label, std::move(x), std::move(y), colour, false});
  }
  return plot;
}

}  // namespace granulab::pictures
