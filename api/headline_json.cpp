#include "api/headline_json.h"

namespace granulab::api {

using nlohmann::json;

namespace {

json text_or_null(const char* s) { return s ? json(s) : json(); }

json scale_json(const Scale& s) {
  return {{"factor", s.factor}, {"unit", s.unit}, {"per_field", text_or_null(s.per_field)}};
}

json axis_json(const Axis& a) {
  return {{"label", a.label}, {"natural", scale_json(a.natural)}, {"si", scale_json(a.si)}};
}

}  // namespace

json headline_json(const Headline& h) {
  json x = axis_json(h.x);
  x["column"] = h.x_column;
  json series = json::array(), values = json::array(), tables = json::array();
  for (const HeadlineSeries& s : h.series)
    series.push_back({{"label", s.label}, {"column", s.column}, {"si_column", s.si_column ? s.si_column : s.column}});
  for (const KeyValue& v : h.values)
    values.push_back({{"key", v.key},
                      {"label", v.label},
                      {"unit", v.unit},
                      {"at_x", text_or_null(v.at_x)},
                      {"at_y", text_or_null(v.at_y)},
                      {"status", text_or_null(v.status)}});
  for (const SummaryTable& t : h.tables) tables.push_back({{"key", t.key}, {"title", t.title}});
  const json events = h.events.list ? json{{"list", h.events.list}, {"x", h.events.x}, {"label", h.events.label}}
                                    : json(nullptr);
  return {{"x", x},           {"y", axis_json(h.y)}, {"series", series},           {"values", values},
          {"tables", tables}, {"note", text_or_null(h.note)}, {"events", events}};
}

const json* value_at_path(const json& j, const std::string& dotted) {
  const json* at = &j;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    const std::string key = dotted.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!at->is_object() || !at->contains(key)) return nullptr;
    at = &(*at)[key];
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return at;
}

std::optional<double> number_at_path(const json& j, const std::string& dotted) {
  const json* at = value_at_path(j, dotted);
  if (!at || !at->is_number()) return std::nullopt;
  return at->get<double>();
}

std::optional<std::string> missing_reason(const json& summary, const std::string& status) {
  const json* group = value_at_path(summary, status);
  if (!group || !group->is_object() || !group->contains("found") || !(*group)["found"].is_boolean() ||
      (*group)["found"].get<bool>())
    return std::nullopt;
  return group->contains("reason") && (*group)["reason"].is_string() ? (*group)["reason"].get<std::string>() : "none";
}

std::optional<std::string> missing_reason(const json& summary, const char* status) {
  if (!status) return std::nullopt;
  return missing_reason(summary, std::string(status));
}

std::optional<double> scale_divisor(const Scale& s, const json& spec) {
  if (!s.per_field) return 1.0;
  const auto v = number_at_path(spec, s.per_field);
  if (!v || !(*v > 0)) return std::nullopt;
  return *v;
}

}  // namespace granulab::api
