// Results to JSON and CSV: summary.json and curve.csv of CONTRACT.md.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "engine/experiments/two_cube_sliding.h"

namespace granulab::api {

/// Engine version recorded with every result.
const char* engine_version();

nlohmann::json summary_json(const TwoCubeResult& r, const nlohmann::json& normalized_spec);
/// Header row first: slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force
std::string curve_csv(const TwoCubeResult& r);

}  // namespace granulab::api
