// How every route answers: JSON bodies and errors that name the bad field, path ids, query integers.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "server/http/message.h"

namespace granulab::server::http {

/// A JSON answer (invalid UTF-8 in quoted input is replaced, never thrown on).
void reply(Response& res, int status, const nlohmann::json& body);
/// {"error": {"code", "message", "field"}} with `status`.
void error(Response& res, int status, const std::string& code, const std::string& message,
           const std::string& field = "");
/// A path id of 1 to 18 digits; nullopt for anything else (then the route answers 404).
std::optional<std::int64_t> path_id(const std::string& digits);
/// Reads ?name= as an integer in [lo, hi] into value (untouched when absent); false after a 400 naming it.
bool query_int(const Request& req, Response& res, const char* name, long lo, long hi, long& value);
/// Reads ?name= as a finite number in (lo, hi] into value (untouched when absent); false after a 400 naming it.
bool query_number(const Request& req, Response& res, const char* name, double lo, double hi, std::optional<double>& value);
/// Reads ?name= as true or false (`fallback` when absent); false after a 400 naming it.
bool query_bool(const Request& req, Response& res, const char* name, bool fallback, bool& value);

}  // namespace granulab::server::http
