// The experiment specification (docs/api.md, docs/spec.md): JSON in, a registered experiment with validated
// parameters out. Every field has the paper's default; unknown fields and out-of-range values are errors
// that name the field. The normalised spec (all defaults filled in) is what a result is stored and
// hashed with. Which fields exist is the experiments' business (engine/experiments/registry.h); this
// file only adds the fields every job has: experiment, label and run.threads.
#pragma once

#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "api/spec_error.h"
#include "engine/experiments/registry.h"

namespace granulab::api {

/// The fields every job has, whatever its experiment.
struct JobFields {
  std::string experiment;  ///< a registered name; the first registered by default
  std::string label;       ///< free text, at most 200 characters
  int threads = 0;         ///< OpenMP threads, 0 = all cores
};
/// Visits them (section "" and "run"); the spec reader and the docs both use it.
void visit_job_fields(ParameterVisitor& v, JobFields& f);

struct Spec {
  const ExperimentType* type = nullptr;          ///< the registered experiment
  std::shared_ptr<const Experiment> experiment;  ///< holding the spec's parameters
  std::string label;
  int threads = 0;            ///< 0 = all cores
  nlohmann::json normalized;  ///< the spec with every default filled in

  const char* name() const { return type ? type->name : ""; }
  /// The experiment as its own type (tests and tools that know which one they asked for).
  template <class E>
  const E& as() const {
    return dynamic_cast<const E&>(*experiment);
  }
};

/// Parses and validates; throws SpecError.
Spec parse_spec(const nlohmann::json& document);
/// Parses text (invalid JSON is a SpecError with code "invalid_json").
Spec parse_spec_text(const std::string& text);

}  // namespace granulab::api
