// A finished run's summary.json: the experiment's own summary fields (ExperimentResult::write_summary)
// plus what every job carries: experiment, engine_version, the normalised spec, and "units", the unit
// of every number by its dotted key (e.g. "first_yield.deviator": "Pa").
#pragma once

#include <nlohmann/json.hpp>

#include "api/spec.h"

namespace granulab::api {

nlohmann::json summary_json(const Spec& spec, const ExperimentResult& result);
/// The experiment's rigid-grain yield estimate (Experiment::yield_estimate) as the summary's "yield_estimate"
/// group, with "units"; null when it has none.
nlohmann::json yield_estimate_json(const Experiment& experiment);

/// The SummaryWriter that builds JSON (exposed for tests).
class JsonSummaryWriter : public SummaryWriter {
 public:
  void number(const char* key, double value, const char* unit) override;
  void count(const char* key, std::uint64_t value) override;
  void flag(const char* key, bool value) override;
  void text(const char* key, const std::string& value) override;
  void begin_group(const char* key) override;
  void end_group() override;
  void begin_list(const char* key) override;
  void end_list() override;

  nlohmann::json& document() { return root_; }
  const nlohmann::json& units() const { return units_; }

 private:
  nlohmann::json& slot(const char* key);  // where the next value goes
  std::string path(const char* key) const;

  nlohmann::json root_ = nlohmann::json::object();
  nlohmann::json units_ = nlohmann::json::object();
  struct Level {
    nlohmann::json* node;
    std::string path;  // dotted prefix, "[]" for list elements
  };
  std::vector<Level> stack_{{&root_, ""}};
};

}  // namespace granulab::api
