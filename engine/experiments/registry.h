// The experiment registry: every experiment, registered once (registry.cpp). The spec reader, the
// runner, the CLI, the server, the API schema and the docs find experiments here and nowhere else.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/framework/experiment.h"

namespace granulab {

struct ExperimentType {
  const char* name;                       ///< the spec's "experiment" value
  const char* title;                      ///< one line for the docs and the API, with the paper's section and figures
  std::unique_ptr<Experiment> (*make)();  ///< an instance holding the paper's defaults
};

/// Every registered experiment; the first is the default of a spec without "experiment".
const std::vector<ExperimentType>& experiment_types();
/// The registered experiment of that name, or nullptr.
const ExperimentType* find_experiment_type(const std::string& name);

}  // namespace granulab
