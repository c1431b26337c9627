// A sweep: one base spec and lists of values for some of its fields (dotted keys), expanded into the
// specs of its jobs, every one validated before any job exists (docs/api.md, "Sweeps").
//   {"spec": {...}, "vary": {"loading.confining_pressure": [10e3, 30e3, 60e3]}, "mode": "product", "label": ""}
// "product" makes every combination (keys in alphabetical order, the last varying fastest); "zip" takes the
// lists side by side.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/spec.h"

namespace granulab::api {

struct SweepPoint {
  nlohmann::json values;  ///< {"dotted.key": value} of this point
  Spec spec;              ///< the validated spec of its job
};

struct Sweep {
  std::string label, mode;
  nlohmann::json base, vary;  ///< as given (vary's keys in the order given)
  std::vector<SweepPoint> points;
};

/// Reads and expands a sweep request; throws SpecError naming the field: "spec", "vary", "mode", "label",
/// or "vary.<dotted key>" for a value the spec refuses (the message gives the value and why).
/// At most `max_jobs` points, and at most `max_bytes` of normalised specs in all (checked on the base spec's
/// size before any point is made, then exactly).
Sweep parse_sweep(const nlohmann::json& request, std::size_t max_jobs, std::size_t max_bytes = 16000000);

}  // namespace granulab::api
