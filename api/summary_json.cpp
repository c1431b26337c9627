#include "api/summary_json.h"

#include <optional>

#include "api/engine_version.h"

namespace granulab::api {

std::string JsonSummaryWriter::path(const char* key) const {
  const std::string& prefix = stack_.back().path;
  if (stack_.back().node->is_array()) return prefix + "[]";  // an element: its key is ignored (may be null)
  return prefix.empty() ? key : prefix + "." + key;
}

nlohmann::json& JsonSummaryWriter::slot(const char* key) {
  nlohmann::json& node = *stack_.back().node;
  if (node.is_array()) {
    node.push_back(nullptr);
    return node.back();
  }
  return node[key];
}

void JsonSummaryWriter::number(const char* key, double value, const char* unit) {
  slot(key) = value;
  units_[path(key)] = unit;
}

void JsonSummaryWriter::count(const char* key, std::uint64_t value) {
  slot(key) = value;
  units_[path(key)] = "-";  // a count has a unit too: none
}

void JsonSummaryWriter::flag(const char* key, bool value) { slot(key) = value; }

void JsonSummaryWriter::text(const char* key, const std::string& value) { slot(key) = value; }

void JsonSummaryWriter::begin_group(const char* key) {
  nlohmann::json& group = slot(key);
  group = nlohmann::json::object();
  stack_.push_back({&group, path(key)});
}

void JsonSummaryWriter::end_group() { stack_.pop_back(); }

void JsonSummaryWriter::begin_list(const char* key) {
  nlohmann::json& list = slot(key);
  list = nlohmann::json::array();
  stack_.push_back({&list, path(key)});
}

void JsonSummaryWriter::end_list() { stack_.pop_back(); }

nlohmann::json summary_json(const Spec& spec, const ExperimentResult& result) {
  JsonSummaryWriter w;
  result.write_summary(w);
  nlohmann::json s = std::move(w.document());
  s["experiment"] = spec.name();
  s["engine_version"] = engine_version();
  s["spec"] = spec.normalized;
  s["units"] = w.units();
  return s;
}

nlohmann::json yield_estimate_json(const Experiment& experiment) {
  const std::optional<YieldEstimate> e = experiment.yield_estimate();
  if (!e) return nullptr;
  JsonSummaryWriter w;
  write_yield_estimate(w, *e);
  nlohmann::json out = w.document()["yield_estimate"], units = nlohmann::json::object();
  for (const auto& [key, unit] : w.units().items()) units[key.substr(key.find('.') + 1)] = unit;
  out["units"] = units;
  return out;
}

}  // namespace granulab::api
