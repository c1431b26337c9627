#include "server/http/replies.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace granulab::server::http {

using nlohmann::json;

void reply(Response& res, int status, const json& body) {
  res.status = status;
  // Messages may quote what a request sent: invalid UTF-8 is replaced, never thrown on.
  res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace) + "\n", "application/json");
}

void error(Response& res, int status, const std::string& code, const std::string& message, const std::string& field) {
  reply(res, status, {{"error", {{"code", code}, {"message", message}, {"field", field}}}});
}

// A path id of 1 to 18 digits (the route's regex has already checked they are digits); anything longer
// cannot be a job, snapshot or row number, so it is simply not found. No exception either way.
std::optional<std::int64_t> path_id(const std::string& digits) {
  if (digits.empty() || digits.size() > 18) return std::nullopt;
  std::int64_t v = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    v = 10 * v + (c - '0');
  }
  return v;
}

// Query integers with a range; a bad value is a 400 that names the parameter.
bool query_int(const Request& req, Response& res, const char* name, long lo, long hi, long& value) {
  if (!req.has_param(name)) return true;
  const std::string text = req.get_param_value(name);
  const bool negative = !text.empty() && text[0] == '-';
  if (const auto v = path_id(negative ? text.substr(1) : text)) {
    value = negative ? -*v : *v;
    if (value >= lo && value <= hi) return true;
  }
  error(res, 400, "out_of_range",
        std::string("'") + name + "' must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
            "], got '" + text + "'",
        name);
  return false;
}

bool query_number(const Request& req, Response& res, const char* name, double lo, double hi,
                  std::optional<double>& value) {
  if (!req.has_param(name)) return true;
  const std::string text = req.get_param_value(name);
  char* end = nullptr;
  const double v = text.empty() || text.size() > 40 ? NAN : std::strtod(text.c_str(), &end);
  if (std::isfinite(v) && end && *end == '\0' && v > lo && v <= hi) {
    value = v;
    return true;
  }
  char range[96];
  std::snprintf(range, sizeof range, "(%g, %g]", lo, hi);
  error(res, 400, "out_of_range", std::string("'") + name + "' must be a number in " + range + ", got '" +
                                      text.substr(0, 40) + "'", name);
  return false;
}

bool query_bool(const Request& req, Response& res, const char* name, bool fallback, bool& value) {
  const std::string text = req.has_param(name) ? req.get_param_value(name) : (fallback ? "true" : "false");
  if (text == "true" || text == "false") {
    value = text == "true";
    return true;
  }
  error(res, 400, "invalid_value", std::string("'") + name + "' must be true or false, got '" + text + "'", name);
  return false;
}

}  // namespace granulab::server::http
