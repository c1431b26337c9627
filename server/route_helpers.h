// What every route file shares: JSON answers and errors, path ids, the query-parameter check and query
// integers. Include after any header that pulls in Eigen: cpp-httplib brings <resolv.h>, whose `_res`
// macro breaks Eigen.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/store/job_store.h"

#include <httplib.h>

namespace granulab::server::http {

/// A JSON answer (invalid UTF-8 in quoted input is replaced, never thrown on).
void reply(httplib::Response& res, int status, const nlohmann::json& body);
/// {"error": {"code", "message", "field"}} with `status`.
void error(httplib::Response& res, int status, const std::string& code, const std::string& message,
           const std::string& field = "");
/// A path id of 1 to 18 digits; nullopt for anything else (then the route answers 404).
std::optional<std::int64_t> path_id(const std::string& digits);
/// The handler, after a 400 naming any query parameter not in `known`.
httplib::Server::Handler only(std::vector<std::string> known, httplib::Server::Handler handler);
/// Reads ?name= as an integer in [lo, hi] into value (untouched when absent); false after a 400 naming it.
bool query_int(const httplib::Request& req, httplib::Response& res, const char* name, long lo, long hi, long& value);
/// The job's curve in the columns form ({"columns": [...], name: [values]}): the stored one of a finished
/// job, the rows so far of a running one, what a cancelled or failed one computed; nullopt when none.
std::optional<nlohmann::json> curve_columns(JobStore& store, const JobRecord& job);
/// The job's curve drawn (api/pictures), titled with its label (or "job N") and, unless it succeeded, its
/// status; nullopt when it has no rows yet.
std::optional<std::string> job_curve_svg(JobStore& store, const JobRecord& job);
/// Stored JSON text parsed, or null when it is empty or unreadable (never throws).
nlohmann::json parsed_or_null(const std::string& text);
/// A running job's latest curve row as {column: value} (its strain and stresses now), or null.
nlohmann::json latest_values(JobStore& store, const JobRecord& job);
/// The job's warnings (from its summary; criteria the run missed), an empty array when none.
nlohmann::json warnings_of(const JobRecord& job);
/// The job as GET /v1/jobs lists it (`full`: with spec, hash, version and summary, as GET /v1/jobs/{id}).
nlohmann::json job_json(const JobRecord& j, bool full);

}  // namespace granulab::server::http
