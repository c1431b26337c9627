// The job routes of docs/api.md ("HTTP API"): submit (with its dry run and reuse), list, read, delete,
// re-prioritise, cancel, and a job's curve and snapshot list. Handlers parse, check access and admission,
// and talk to the store; the executor runs the jobs.
#include "api/curve_format.h"
#include "api/engine_version.h"
#include "api/runner.h"
#include "api/spec.h"
#include "server/http/replies.h"
#include "server/job_views.h"
#include "server/routes/routes.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

void mount_job_routes(Router& router, const RouteContext& c) {
  router.post("/v1/jobs", {"reuse", "priority", "dry_run"}, [c](const http::Request& req, http::Response& res) {
    api::Spec spec;
    try {
      spec = api::parse_spec_text(req.body);
    } catch (const api::SpecError& e) {
      return error(res, 400, e.code, e.what(), e.field);
    }
    long priority = 0;
    if (!query_int(req, res, "priority", -100, 100, priority)) return;
    if (!c.access.may_use_priority(c.access.who(req), priority, res, "priority")) return;
    // A dry run: the spec is valid; what it would cost here, and nothing queued.
    const std::string dry_run = req.has_param("dry_run") ? req.get_param_value("dry_run") : "false";
    if (dry_run != "true" && dry_run != "false")
      return error(res, 400, "invalid_value", "'dry_run' must be true or false, got '" + dry_run + "'", "dry_run");
    if (dry_run == "true") return reply(res, 200, c.admission.cost_estimate(spec));
    if (!c.admission.within_budget(spec, res)) return;
    const std::string hash = api::spec_hash(spec.normalized);
    const std::string experiment = spec.normalized["experiment"].get<std::string>();
    const std::string reuse = req.has_param("reuse") ? req.get_param_value("reuse") : "false";
    if (reuse != "true" && reuse != "false")
      return error(res, 400, "invalid_value", "'reuse' must be true or false, got '" + reuse + "'", "reuse");
    const User who = c.access.who(req);
    if (reuse == "true") {
      if (const auto id = c.store.find_succeeded(hash, api::engine_version(), c.access.reuse_owner(who)))
        return reply(res, 200, {{"id", *id}, {"status", api::status_name(JobStatus::succeeded)}, {"reused", true}});
    }
    if (!c.admission.within_queue_quota(who, 1, res)) return;
    const double bytes = c.admission.expected_store_bytes(spec);
    if (!c.admission.within_user_storage(who, bytes, res)) return;
    if (!c.admission.within_storage(bytes, res)) return;
    const std::int64_t id = c.store.submit(spec.normalized.dump(), experiment, spec.label, hash, api::engine_version(),
                                           who.name, int(priority), bytes);
    c.executor.notify();
    reply(res, 201, {{"id", id}, {"status", api::status_name(JobStatus::queued)}});
  });

  router.get("/v1/jobs", {"status", "owner", "limit", "offset"}, [c](const http::Request& req, http::Response& res) {
    long limit = 50, offset = 0;
    if (!query_int(req, res, "limit", 1, 1000, limit) || !query_int(req, res, "offset", 0, 1L << 40, offset)) return;
    const std::string status_text = req.get_param_value("status");
    const std::optional<JobStatus> status = api::parse_job_status(status_text);
    if (!status_text.empty() && !status)  // an empty ?status= is no filter
      return error(res, 400, "invalid_value",
                   "'status' must be one of: " + api::job_status_names() + ", got '" + status_text + "'", "status");
    const auto owner = c.access.listing_owner(req, res, "jobs");
    if (!owner) return;
    json jobs = json::array();
    for (const JobRecord& j : c.store.list(status, int(limit), offset, *owner)) {
      jobs.push_back(job_json(j, false));
      if (j.status == JobStatus::running)
        if (json latest = latest_values(c.store, j); !latest.is_null()) jobs.back()["latest"] = std::move(latest);
    }
    reply(res, 200, {{"jobs", jobs}, {"limit", limit}, {"offset", offset}});
  });

  router.get(R"(/v1/jobs/(\d+))", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    json out = job_json(*job, true);
    if (json latest = latest_values(c.store, *job); !latest.is_null()) out["latest"] = std::move(latest);
    reply(res, 200, out);
  });

  router.del(R"(/v1/jobs/(\d+))", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "delete", true);
    if (!job) return;
    switch (c.store.remove(job->id)) {
      case JobStore::WriteResult::done: return reply(res, 200, {{"id", job->id}, {"deleted", true}});
      case JobStore::WriteResult::not_found: return error(res, 404, "not_found", "no job " + std::to_string(job->id));
      case JobStore::WriteResult::wrong_state:
        return error(res, 409, "wrong_state",
                     "job " + std::to_string(job->id) + " is " + api::status_name(job->status) + ": cancel it first");
    }
  });

  router.post(R"(/v1/jobs/(\d+)/priority)", {"value"}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "re-prioritise", true);
    if (!job) return;
    long priority = 0;
    if (!req.has_param("value"))
      return error(res, 400, "missing", "'value' (the new priority, -100 to 100) is required", "value");
    if (!query_int(req, res, "value", -100, 100, priority)) return;
    if (!c.access.may_use_priority(c.access.who(req), priority, res, "value")) return;
    switch (c.store.set_priority(job->id, int(priority))) {
      case JobStore::WriteResult::done: return reply(res, 200, {{"id", job->id}, {"priority", priority}});
      case JobStore::WriteResult::not_found: return error(res, 404, "not_found", "no job " + std::to_string(job->id));
      case JobStore::WriteResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is no longer queued");
    }
  });

  router.post(R"(/v1/jobs/(\d+)/cancel)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "cancel", true);
    if (!job) return;
    const std::int64_t id = job->id;
    switch (c.store.request_cancel(id)) {
      case JobStore::CancelResult::cancelled_queued:
        c.executor.cancel_requested(id);  // on a cluster it may be pending there
        return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::cancelled)}});
      case JobStore::CancelResult::requested_running:
        c.executor.cancel_requested(id);
        return reply(res, 202,
                     {{"id", id}, {"status", api::status_name(JobStatus::running)}, {"cancel_requested", true}});
      case JobStore::CancelResult::not_found:
        return error(res, 404, "not_found", "no job " + std::string(req.matches[1]));
      case JobStore::CancelResult::wrong_state:
        return error(res, 409, "wrong_state", "job " + std::to_string(id) + " has already finished");
    }
  });

  router.get(R"(/v1/jobs/(\d+)/curve)", {"format"}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    const std::int64_t id = job->id;
    // A finished job's stored curve; a running job's rows so far; what a cancelled or failed one computed.
    const std::string format = req.has_param("format") ? req.get_param_value("format") : "json";
    if (format != "json" && format != "csv")
      return error(res, 400, "invalid_value", "'format' must be json or csv, got '" + format + "'", "format");
    const bool csv = format == "csv";
    if (job->status == JobStatus::succeeded && !csv)
      if (const auto json_text = c.store.curve_json(id)) return res.set_content(*json_text, "application/json");
    const auto text = c.store.live_curve_csv(id);
    if (!text)
      return error(res, 409, "wrong_state",
                   "job " + std::to_string(id) + " is " + api::status_name(job->status) + " and has no curve yet");
    if (csv) return res.set_content(*text, "text/csv");
    const auto curve = curve_columns(c.store, *job);  // from the stored rows' values, not from the CSV
    res.set_content(curve ? curve->dump() : api::curve_csv_to_json(*text).dump(), "application/json");
  });

  router.get(R"(/v1/jobs/(\d+)/snapshots)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = c.access.job_for(c.store, req, res, "read", false);
    if (!job) return;
    const std::int64_t id = job->id;
    json list = json::array();
    for (const auto& s : c.store.snapshots(id))
      list.push_back({{"index", s.index}, {"strain", s.strain}, {"bytes", s.bytes}});
    reply(res, 200, {{"snapshots", list}});
  });
}

}  // namespace granulab::server
