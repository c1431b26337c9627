// Results to JSON and CSV: summary.json and curve.csv of CONTRACT.md.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "engine/experiments/crystal_compression.h"
#include "engine/experiments/two_cube_sliding.h"

namespace granulab::api {

/// Engine version recorded with every result.
const char* engine_version();

nlohmann::json summary_json(const TwoCubeResult& r, const nlohmann::json& normalized_spec);
/// Header row first: slide_over_size,normal_over_p0,tangential_over_p0,normal_force,tangential_force
std::string curve_csv(const TwoCubeResult& r);

nlohmann::json summary_json(const CrystalResult& r, const nlohmann::json& normalized_spec);
/// Header row first: strain,stress_top,stress_bottom,deviator,lateral_strain_x,lateral_strain_y,
/// lateral_stress,kinetic_elastic_ratio,contacts,sliding_contacts
std::string curve_csv(const CrystalResult& r);
/// The header line and one row line (newline included) of the crystal curve, for writing as it runs.
std::string crystal_curve_header();
std::string crystal_curve_row(const CrystalRow& row);
/// The first yield peak of a crystal curve: once the deviator exceeds 0.1 p0, the largest deviator
/// before it first falls `drop` (relative) below its running maximum. Returns {strain, deviator};
/// {0, 0} if the deviator never reaches 0.1 p0.
std::pair<double, double> first_yield_peak(const std::vector<CrystalRow>& curve, double p0, double drop = 0.02);

}  // namespace granulab::api
