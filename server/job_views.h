// A stored job as the routes show it: its JSON, its warnings, its latest curve row, its curve in the
// columns form and drawn. Shared by the job, sweep, picture and export routes; no route in it.
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "api/pictures/curve_pictures.h"
#include "engine/analysis/grain_snapshot.h"
#include "server/http/message.h"
#include "server/store/job_store.h"

namespace granulab::server {

/// Stored JSON text parsed, or null when it is empty or unreadable (never throws).
nlohmann::json parsed_or_null(const std::string& text);
/// The job as GET /v1/jobs lists it (`full`: with spec, hash, version and summary, as GET /v1/jobs/{id}).
nlohmann::json job_json(const JobRecord& j, bool full);
/// The job's warnings (from its summary; criteria the run missed), an empty array when none.
nlohmann::json warnings_of(const JobRecord& job);
/// A running job's latest curve row as {column: value} (its strain and stresses now), or null.
nlohmann::json latest_values(JobStore& store, const JobRecord& job);
/// The job's curve in the columns form ({"columns": [...], name: [values]}): the stored one of a finished
/// job, the rows so far of a running one, what a cancelled or failed one computed; nullopt when none.
std::optional<nlohmann::json> curve_columns(JobStore& store, const JobRecord& job);
/// The job's curve drawn (api/pictures), titled with its label (or "job N") and, unless it succeeded, its
/// status; nullopt when it has no rows yet.
std::optional<std::string> job_curve_svg(JobStore& store, const JobRecord& job,
                                         const pictures::CurveChoice& choice = {});
/// Snapshot `index` (the path's digits) of `job` as stored; nullopt after answering 404 (no such snapshot) or 500
/// (unreadable).
std::optional<GrainSnapshot> stored_snapshot(JobStore& store, const JobRecord& job, const std::string& index,
                                             http::Response& res);
/// The reader's choice of units (?units=natural|si) and column (?y=, one of the experiment's curve
/// columns) for the curve pictures; false after a 400 naming the parameter.
bool curve_choice(const http::Request& req, http::Response& res, const nlohmann::json& spec,
                  pictures::CurveChoice& choice);

}  // namespace granulab::server
