// The sweep routes of docs/api.md ("Sweeps"): a sweep is validated whole before any of its jobs exists.
#include "api/bounded_json.h"
#include "api/pictures/curve_pictures.h"
#include "api/spec.h"
#include "api/sweep.h"
#include "api/engine_version.h"
#include "api/runner.h"
#include "server/routes/routes.h"
#include "server/http/replies.h"
#include "server/job_views.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

void mount_sweep_routes(Router& router, const RouteContext& c) {
  // A sweep: every point validated (and within the budget and the quota) before any job is created.
  router.post("/v1/sweeps", {"priority"}, [c](const http::Request& req, http::Response& res) {
    api::Sweep sweep;
    try {
      sweep = api::parse_sweep(api::parse_bounded_json(req.body), c.max_jobs_per_sweep, c.max_sweep_bytes);
    } catch (const api::SpecError& e) {
      return error(res, 400, e.code, e.what(), e.field);
    }
    long priority = 0;
    if (!query_int(req, res, "priority", -100, 100, priority)) return;
    if (!c.access.may_use_priority(c.access.who(req), priority, res, "priority")) return;
    // Over budget: which point, by its values.
    for (const api::SweepPoint& p : sweep.points)
      if (const std::string problem = c.admission.budget_problem(p.spec); !problem.empty())
        return error(res, 400, "over_budget", "the point " + p.values.dump() + ": " + problem, "vary");
    const User who = c.access.who(req);
    if (!c.admission.within_queue_quota(who, sweep.points.size(), res)) return;
    std::vector<JobStore::SweepJob> jobs;
    double bytes = 0;
    for (const api::SweepPoint& p : sweep.points) {
      // "<sweep or spec label> (key=value, ...)", or just the values: what tells the sweep's jobs apart.
      std::string values;
      for (const auto& [key, value] : p.values.items())
        values += (values.empty() ? "" : ", ") + key + "=" + value.dump();
      const std::string base = sweep.label.empty() ? p.spec.label : sweep.label;
      const std::string label = base.empty() ? values : base + " (" + values + ")";
      const double job_bytes = c.admission.expected_store_bytes(p.spec);
      bytes += job_bytes;
      jobs.push_back({p.spec.normalized.dump(), p.spec.normalized["experiment"].get<std::string>(), label,
                      api::spec_hash(p.spec.normalized), p.values.dump(), job_bytes});
    }
    if (!c.admission.within_user_storage(who, bytes, res)) return;
    if (!c.admission.within_storage(bytes, res)) return;
    SweepRecord record;
    record.label = sweep.label, record.owner = who.name, record.mode = sweep.mode;
    record.base_json = sweep.base.dump(), record.vary_json = sweep.vary.dump();
    const auto [id, ids] = c.store.submit_sweep(record, jobs, api::engine_version(), int(priority));
    c.executor.notify();
    reply(res, 201, {{"id", id}, {"jobs", ids}});
  });

  router.get("/v1/sweeps", {"owner", "limit", "offset"}, [c](const http::Request& req, http::Response& res) {
    long limit = 50, offset = 0;
    if (!query_int(req, res, "limit", 1, 1000, limit) || !query_int(req, res, "offset", 0, 1L << 40, offset)) return;
    const auto owner = c.access.listing_owner(req, res, "sweeps");
    if (!owner) return;
    json sweeps = json::array();
    for (const SweepRecord& s : c.store.list_sweeps(int(limit), offset, *owner))
      sweeps.push_back({{"id", s.id},
                        {"label", s.label},
                        {"owner", s.owner},
                        {"mode", s.mode},
                        {"vary", json::parse(s.vary_json, nullptr, false)},
                        {"created_ms", s.created_ms}});
    reply(res, 200, {{"sweeps", sweeps}, {"limit", limit}, {"offset", offset}});
  });

  // Its jobs with their values, status, progress, and (when done) their headline's key values.
  router.get(R"(/v1/sweeps/(\d+))", {}, [c](const http::Request& req, http::Response& res) {
    const auto sweep = c.access.sweep_for(c.store, req, res, "read", false);
    if (!sweep) return;
    json jobs = json::array();
    std::map<std::string, int> counts;
    for (const JobRecord& j : c.store.sweep_jobs(sweep->id)) {
      json item = {{"id", j.id},
                   {"status", api::status_name(j.status)},
                   {"progress", j.progress},
                   {"values", json::parse(j.sweep_values, nullptr, false)}};
      if (j.status == JobStatus::running && j.eta_seconds >= 0) item["eta_seconds"] = j.eta_seconds;
      if (!j.error.empty()) item["error"] = j.error;
      if (json warnings = warnings_of(j); !warnings.empty()) item["warnings"] = std::move(warnings);
      if (json latest = latest_values(c.store, j); !latest.is_null()) item["latest"] = std::move(latest);
      // The key values of its experiment's headline, each with the summary group it belongs to.
      if (!j.summary_json.empty()) {
        const json summary = json::parse(j.summary_json, nullptr, false);
        for (const KeyValue& v : pictures::headline_for(parsed_or_null(j.spec_json)).values)
          for (const char* path : {v.key, v.status}) {  // the value's group, and the one saying whether it was found
            if (!path) continue;
            const std::string key = std::string(path).substr(0, std::string(path).find('.'));
            if (summary.is_object() && summary.contains(key)) item[key] = summary[key];
          }
      }
      ++counts[api::status_name(j.status)];
      jobs.push_back(item);
    }
    reply(res, 200,
          {{"id", sweep->id},
           {"label", sweep->label},
           {"owner", sweep->owner},
           {"mode", sweep->mode},
           {"spec", json::parse(sweep->base_json, nullptr, false)},
           {"vary", json::parse(sweep->vary_json, nullptr, false)},
           {"created_ms", sweep->created_ms},
           {"counts", counts},
           {"jobs", jobs}});
  });

  // Cancels what has not finished: queued jobs at once, running ones within a second.
  router.post(R"(/v1/sweeps/(\d+)/cancel)", {}, [c](const http::Request& req, http::Response& res) {
    const auto sweep = c.access.sweep_for(c.store, req, res, "cancel", true);
    if (!sweep) return;
    int cancelled = 0, requested = 0;
    for (const JobRecord& j : c.store.sweep_jobs(sweep->id)) {
      const auto r = c.store.request_cancel(j.id);
      cancelled += r == JobStore::CancelResult::cancelled_queued;
      requested += r == JobStore::CancelResult::requested_running;
      if (r == JobStore::CancelResult::cancelled_queued || r == JobStore::CancelResult::requested_running)
        c.executor.cancel_requested(j.id);
    }
    reply(res, 200, {{"id", sweep->id}, {"cancelled", cancelled}, {"cancel_requested", requested}});
  });
}

}  // namespace granulab::server
