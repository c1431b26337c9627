// An experiment's headline (engine/framework/headline.h) as JSON, as GET /v1/experiments serves it for
// the web page and the CLI: {"x": {"column", "label", "natural": scale, "si": scale}, "y": {"label",
// "natural", "si"}, "series": [{"label", "column", "si_column"}], "values": [{"key", "label", "unit",
// "at_x", "at_y", "status"}], "tables": [{"key", "title"}], "note"}, a scale being {"factor", "unit", "per_field"}.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/framework/headline.h"

namespace granulab::api {

nlohmann::json headline_json(const Headline& h);
/// The value at a dotted path of a JSON object ("first_yield.strain"), if it is a number.
std::optional<double> number_at_path(const nlohmann::json& j, const std::string& dotted);
/// The value at a dotted path of objects, or nullptr.
const nlohmann::json* value_at_path(const nlohmann::json& j, const std::string& dotted);
/// When the summary group at `status` (a key value's, dotted; null: none) says {"found": false}, the reason it gives
/// ("none" without one): the reader shows that, not a number. nullopt when found or when there is no such group.
std::optional<std::string> missing_reason(const nlohmann::json& summary, const char* status);
std::optional<std::string> missing_reason(const nlohmann::json& summary, const std::string& status);
/// The divisor of a scale for a job of `spec` (the normalised spec): its per_field's value, 1 without one;
/// nullopt when the spec lacks it or it is not positive.
std::optional<double> scale_divisor(const Scale& s, const nlohmann::json& spec);

}  // namespace granulab::api
