// The experiment specification (CONTRACT.md): JSON in, validated engine parameters out.
// Every field has the paper's default; unknown fields and out-of-range values are errors that name
// the field. The normalised spec (all defaults filled in) is what a result is stored and hashed with.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "api/spec_error.h"
#include "engine/experiments/crystal_compression.h"
#include "engine/experiments/two_cube_sliding.h"

namespace granulab::api {

enum class Experiment { two_cube_sliding, crystal_compression };

struct Spec {
  Experiment experiment = Experiment::two_cube_sliding;
  std::string label;
  int threads = 0;             ///< 0 = all cores
  TwoCubeParams two_cube;      ///< filled when experiment == two_cube_sliding
  CrystalParams crystal;       ///< filled when experiment == crystal_compression
  nlohmann::json normalized;   ///< the spec with every default filled in
};

/// Parses and validates; throws SpecError.
Spec parse_spec(const nlohmann::json& document);
/// Parses text (invalid JSON is a SpecError with code "invalid_json").
Spec parse_spec_text(const std::string& text);

}  // namespace granulab::api
