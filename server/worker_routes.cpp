// The routes a job's worker on a cluster talks to (docs/api.md, "Workers"): it fetches its spec and
// checkpoint here and sends back what the store's sink would write locally (curve rows, snapshots,
// progress, checkpoints, the summary). Each request carries the job's own secret in `X-Worker-Token`;
// user tokens do not open these routes, and a worker's secret opens nothing else. Every write is
// idempotent (rows and snapshots by index, the end by state), so a worker may repeat a request whose
// answer it lost, e.g. while the daemon restarted.
#include <algorithm>

#include "api/curve_format.h"
#include "api/engine_version.h"
#include "api/job_sink.h"
#include "engine/core/checkpoint.h"
#include "server/resume_point.h"
#include "server/routes.h"
#include "server/route_helpers.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

namespace {

bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;  // no early exit: the time does not tell how much of a guess was right
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

// A string field of a JSON object, or `fallback` (never throws on a missing or mistyped field).
std::string text(const json& body, const char* key, const std::string& fallback) {
  return body.is_object() && body.contains(key) && body[key].is_string() ? body[key].get<std::string>() : fallback;
}

bool finished(const std::string& status) { return status == "succeeded" || status == "failed" || status == "cancelled"; }

}  // namespace

bool HttpServer::worker_may_send(const std::string& target, const std::string& token) {
  // "/v1/worker/jobs/<id>/..." with that job's secret; called by the connection loop on the request's head.
  static const std::string prefix = "/v1/worker/jobs/";
  if (target.compare(0, prefix.size(), prefix) != 0) return false;
  const std::size_t end = target.find_first_not_of("0123456789", prefix.size());
  const auto id = path_id(target.substr(prefix.size(), end == std::string::npos ? std::string::npos : end - prefix.size()));
  if (!id) return false;
  // The connection loop's thread never waits for the store (a large checkpoint may be being written): it
  // knows the secrets of the active jobs at start-up and of every worker that has been answered since (a
  // worker's first request, its start, is small).
  std::lock_guard<std::mutex> lock(worker_secrets_mutex_);
  const auto it = worker_secrets_.find(*id);
  return it != worker_secrets_.end() && same_secret(it->second, token);
}

void HttpServer::remember_worker_secret(std::int64_t job, const std::string& secret) {
  std::lock_guard<std::mutex> lock(worker_secrets_mutex_);
  if (worker_secrets_.size() > 100000) worker_secrets_.clear();  // bounded: finished jobs' secrets go
  worker_secrets_[job] = secret;
}

std::optional<JobRecord> HttpServer::worker_job(const httplib::Request& req, httplib::Response& res) {
  const auto id = path_id(req.matches[1]);
  const std::optional<JobRecord> job = id ? store_.get(*id) : std::nullopt;
  const std::string expected = job ? store_.worker_token(job->id) : "";
  // An unknown job answers as a wrong secret does: these routes tell nobody which jobs exist.
  if (expected.empty() || !same_secret(expected, req.get_header_value("X-Worker-Token"))) {
    error(res, 403, "forbidden", "this is not the worker of job " + std::string(req.matches[1]) + " (X-Worker-Token)");
    return std::nullopt;
  }
  remember_worker_secret(job->id, expected);
  // A worker of an earlier Slurm job of this job (it was requeued since) may not touch the new run.
  const std::string slurm_job = req.get_header_value("X-Slurm-Job-Id");
  if (!slurm_job.empty() && slurm_job != job->slurm_job_id) {
    error(res, 409, "stale_worker",
          "job " + std::to_string(job->id) + " now runs as Slurm job " + (job->slurm_job_id.empty() ? "(none yet)" : job->slurm_job_id) +
              ", not " + slurm_job);
    return std::nullopt;
  }
  return job;
}

void HttpServer::worker_routes() {
  // Start (or start again): the spec, and whether to resume from the stored checkpoint, whose results the
  // store trims to it now. The job is running from here on.
  router().Get(R"(/v1/worker/jobs/(\d+))", only({"engine_version"}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    if (finished(job->status) || job->cancel_requested)
      return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is " + job->status + (job->cancel_requested ? " (cancel requested)" : ""));
    if (!store_.mark_running(job->id, req.get_header_value("X-Slurm-Job-Id")))
      return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " can no longer start");
    const std::string version = req.has_param("engine_version") ? req.get_param_value("engine_version") : "";
    const std::optional<api::Resume> resume = resume_point(store_, job->id, version);
    json out = {{"id", job->id},
                {"spec", json::parse(job->spec_json)},
                {"checkpoint_seconds", pool_.checkpoint_seconds()},
                {"progress_seconds", 1.0},
                {"resume", bool(resume)}};
    if (resume) out["resume_rows"] = resume->rows, out["resume_snapshots"] = resume->snapshots;
    reply(res, 200, out);
  }));

  // The checkpoint to resume from (api::pack_resume's bytes).
  router().Get(R"(/v1/worker/jobs/(\d+)/checkpoint)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    const auto cp = store_.checkpoint(job->id);
    if (!cp) return error(res, 404, "not_found", "job " + std::to_string(job->id) + " has no checkpoint");
    res.set_content(api::pack_resume({cp->state, std::size_t(cp->rows), std::size_t(cp->snapshots)}),
                    "application/octet-stream");
  }));

  // The curve's header; with resume_rows, a check that the store holds exactly the rows the checkpoint follows.
  router().Post(R"(/v1/worker/jobs/(\d+)/begin)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    if (job->status != "running") return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is " + job->status);
    const json body = json::parse(req.body, nullptr, false);
    if (!body.is_object() || !body.contains("header") || !body["header"].is_string())
      return error(res, 400, "invalid_value", "expected {\"header\": CSV header line, \"resume_rows\": n or null}", "header");
    const std::string header = body["header"].get<std::string>();
    if (body.contains("resume_rows") && body["resume_rows"].is_number_unsigned()) {
      const std::size_t rows = body["resume_rows"].get<std::size_t>();
      const std::string stored = store_.live_curve_csv(job->id).value_or(header);
      const std::string kept = stored.substr(0, api::curve_csv_prefix(stored, rows));
      if (std::size_t(std::count(kept.begin(), kept.end(), '\n')) != rows + 1) {
        store_.discard_partial_results(job->id);
        return error(res, 409, "cannot_resume", "the store does not hold the " + std::to_string(rows) +
                                                    " rows the checkpoint follows: start afresh");
      }
      return reply(res, 200, {{"resume", true}});
    }
    store_.start_curve(job->id, header);
    reply(res, 200, {{"resume", false}});
  }));

  // Rows and snapshots since the last batch, and the progress; the answer says whether a cancel was asked.
  router().Post(R"(/v1/worker/jobs/(\d+)/results)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    if (job->status != "running") return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is " + job->status);
    const json body = json::parse(req.body, nullptr, false);
    std::vector<std::string> lines;
    std::vector<JobStore::SnapshotBlob> snapshots;
    std::size_t first = 0;
    double progress = 0, eta = -1;
    try {
      first = body.at("first_index").get<std::size_t>();
      lines = body.at("lines").get<std::vector<std::string>>();
      for (const json& s : body.at("snapshots"))
        snapshots.push_back({s.at("index").get<int>(), s.at("strain").get<double>(), s.at("data").get<std::string>()});
      progress = body.at("progress").get<double>();
      eta = body.value("eta_seconds", -1.0);
    } catch (const std::exception& e) {
      return error(res, 400, "invalid_value", std::string("malformed results batch: ") + e.what(), "results");
    }
    if (!lines.empty() || !snapshots.empty()) store_.append_results(job->id, first, lines, snapshots);
    store_.set_progress(job->id, progress, eta);
    reply(res, 200, {{"cancel", store_.cancel_requested(job->id)}});
  }));

  // A checkpoint: the state after ?rows= curve rows and ?snapshots= snapshots (all sent before it).
  router().Post(R"(/v1/worker/jobs/(\d+)/checkpoint)", only({"rows", "snapshots", "engine_version"}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    if (job->status != "running") return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " is " + job->status);
    long rows = -1, snapshots = -1;
    if (!query_int(req, res, "rows", 0, 1L << 40, rows) || !query_int(req, res, "snapshots", 0, 1L << 20, snapshots)) return;
    if (rows < 0 || snapshots < 0) return error(res, 400, "missing", "'rows' and 'snapshots' are required", "rows");
    const std::string version = req.has_param("engine_version") ? req.get_param_value("engine_version") : "";
    try {
      CheckpointReader whole(req.body);  // its frame and checksum: a torn upload is refused, not stored
    } catch (const CheckpointError& e) {
      return error(res, 400, "invalid_value", std::string("unreadable checkpoint: ") + e.what(), "checkpoint");
    }
    const JobStore::Checkpoint cp{req.body, rows, snapshots, version};
    store_.append_results(job->id, std::size_t(rows), {}, {}, &cp);
    reply(res, 200, {{"stored", true}});
  }));

  // How the run ended: succeeded (with its summary; the curve is the rows sent), failed, cancelled, or
  // interrupted (a signal: the time limit is near, or Slurm stops it), which the daemon turns into a
  // cancel if one was asked, and otherwise into a requeue that resumes from the last checkpoint.
  router().Post(R"(/v1/worker/jobs/(\d+)/end)", only({}, [this](const httplib::Request& req, httplib::Response& res) {
    const auto job = worker_job(req, res);
    if (!job) return;
    const json body = json::parse(req.body, nullptr, false);
    const std::string outcome = text(body, "outcome", "");
    const std::int64_t id = job->id;
    if (outcome == "succeeded") {
      if (!body.contains("summary") || !body["summary"].is_object())
        return error(res, 400, "invalid_value", "a succeeded run sends its summary", "summary");
      const std::string csv = store_.live_curve_csv(id).value_or("");
      if (store_.succeed(id, body["summary"].dump(), csv, api::curve_csv_to_json(csv).dump()) || job->status == "succeeded")
        return reply(res, 200, {{"id", id}, {"status", "succeeded"}});
    } else if (outcome == "failed") {
      if (store_.fail(id, text(body, "error", "the worker failed")) || job->status == "failed")
        return reply(res, 200, {{"id", id}, {"status", "failed"}});
    } else if (outcome == "cancelled") {
      if (store_.mark_cancelled(id) || job->status == "cancelled") return reply(res, 200, {{"id", id}, {"status", "cancelled"}});
    } else if (outcome == "interrupted") {
      if (job->cancel_requested || job->status == "cancelled") {
        store_.mark_cancelled(id);
        return reply(res, 200, {{"id", id}, {"status", "cancelled"}});
      }
      if (job->status == "running") {
        switch (store_.requeue_for_cluster(id, text(body, "reason", "its worker was interrupted"))) {
          case JobStore::Requeue::requeued:
            pool_.notify();
            return reply(res, 200, {{"id", id}, {"status", "queued"}});
          case JobStore::Requeue::cancelled:
            return reply(res, 200, {{"id", id}, {"status", "cancelled"}});
          case JobStore::Requeue::failed:
            return reply(res, 200, {{"id", id}, {"status", "failed"}});
          case JobStore::Requeue::not_active:
            break;
        }
      }
    } else {
      return error(res, 400, "invalid_value", "'outcome' must be succeeded, failed, cancelled or interrupted", "outcome");
    }
    const auto now = store_.get(id);
    error(res, 409, "wrong_state", "job " + std::to_string(id) + " is " + (now ? now->status : "gone"));
  }));
}

}  // namespace granulab::server
