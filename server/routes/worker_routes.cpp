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
#include "server/http/replies.h"
#include "server/routes/routes.h"
#include "server/store/sqlite.h"

namespace granulab::server {

using nlohmann::json;
using namespace http;

namespace {

// A string field of a JSON object, or `fallback` (never throws on a missing or mistyped field).
std::string text(const json& body, const char* key, const std::string& fallback) {
  return body.is_object() && body.contains(key) && body[key].is_string() ? body[key].get<std::string>() : fallback;
}

// The job of a worker route's path id, if the request carries its worker's secret (else 403 or 409).
std::optional<JobRecord> worker_job(const RouteContext& c, const Request& req, Response& res) {
  const auto id = path_id(req.matches[1]);
  const std::optional<JobRecord> job = id ? c.store.get(*id) : std::nullopt;
  const std::string expected = job ? c.store.worker_token(job->id) : "";
  // An unknown job answers as a wrong secret does: these routes tell nobody which jobs exist.
  if (expected.empty() || !same_secret(expected, req.get_header_value("X-Worker-Token"))) {
    error(res, 403, "forbidden", "this is not the worker of job " + req.matches[1] + " (X-Worker-Token)");
    return std::nullopt;
  }
  c.worker_secrets.remember(job->id, expected);
  // A worker of an earlier Slurm job of this job (it was requeued since) may not touch the new run.
  const std::string slurm_job = req.get_header_value("X-Slurm-Job-Id");
  if (!slurm_job.empty() && slurm_job != job->slurm_job_id) {
    error(res, 409, "stale_worker",
          "job " + std::to_string(job->id) + " now runs as Slurm job " +
              (job->slurm_job_id.empty() ? "(none yet)" : job->slurm_job_id) + ", not " + slurm_job);
    return std::nullopt;
  }
  return job;
}

// A worker's writes are for a running job only (else a 409 saying what it is now).
bool still_running(const JobRecord& job, Response& res) {
  if (job.status == JobStatus::running) return true;
  error(res, 409, "wrong_state", "job " + std::to_string(job.id) + " is " + api::status_name(job.status));
  return false;
}

// A worker's write the store cannot hold: the job fails for it, the reserve file giving the room to say so,
// so that it is neither left `running` nor run again after a restart; the worker is told 507 and stops.
Handler failing_on_full_store(const RouteContext& c, Handler handler) {
  return [c, handler = std::move(handler)](const Request& req, Response& res) {
    try {
      handler(req, res);
    } catch (const sqlite::StoreFull& e) {
      const auto id = path_id(req.matches[1]);
      c.store.release_reserve();
      try {
        if (id)
          c.store.fail(*id, std::string("the server's storage is full (its disk, or --max-db-mb): ") + e.what() +
                                "; what was stored before is kept");
      } catch (const std::exception&) {  // not even that: it stays running and is failed at the next start
      }
      error(res, 507, "storage_full",
            "the server's storage is full (its disk, or --max-db-mb): the job has failed; stop");
    }
  };
}

}  // namespace

void mount_worker_routes(Router& http_router, const RouteContext& c) {
  // Every route here through failing_on_full_store.
  struct Guarded {
    Router& to;
    const RouteContext& c;
    void get(const std::string& pattern, std::vector<std::string> params, Handler h) {
      to.get(pattern, std::move(params), failing_on_full_store(c, std::move(h)));
    }
    void post(const std::string& pattern, std::vector<std::string> params, Handler h) {
      to.post(pattern, std::move(params), failing_on_full_store(c, std::move(h)));
    }
  } router{http_router, c};
  // Start (or start again): the spec, and whether to resume from the stored checkpoint, whose results the
  // store trims to it now. The job is running from here on.
  router.get(R"(/v1/worker/jobs/(\d+))", {"engine_version"}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    if (api::is_finished(job->status) || job->cancel_requested)
      return error(res, 409, "wrong_state",
                   "job " + std::to_string(job->id) + " is " + api::status_name(job->status) +
                       (job->cancel_requested ? " (cancel requested)" : ""));
    if (!c.store.mark_running(job->id, req.get_header_value("X-Slurm-Job-Id")))
      return error(res, 409, "wrong_state", "job " + std::to_string(job->id) + " can no longer start");
    const std::string version = req.has_param("engine_version") ? req.get_param_value("engine_version") : "";
    const std::optional<api::Resume> resume = resume_point(c.store, job->id, version);
    json out = {{"id", job->id},
                {"spec", json::parse(job->spec_json)},
                {"checkpoint_seconds", c.executor.checkpoint_seconds()},
                {"progress_seconds", 1.0},
                {"resume", bool(resume)}};
    if (resume) out["resume_rows"] = resume->rows, out["resume_snapshots"] = resume->snapshots;
    reply(res, 200, out);
  });

  // The checkpoint to resume from: its counts and chunks; each chunk is then a GET of its own.
  router.get(R"(/v1/worker/jobs/(\d+)/checkpoint)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    const auto cp = c.store.checkpoint(job->id);
    if (!cp) return error(res, 404, "not_found", "job " + std::to_string(job->id) + " has no checkpoint");
    reply(res, 200,
          {{"generation", cp->generation}, {"chunks", cp->chunks}, {"bytes", cp->bytes}, {"rows", cp->rows},
           {"snapshots", cp->snapshots}, {"engine_version", cp->engine_version}});
  });
  router.get(R"(/v1/worker/jobs/(\d+)/checkpoint/(\d+)/(\d+))", {},
             [c](const http::Request& req, http::Response& res) {
               const auto job = worker_job(c, req, res);
               if (!job) return;
               const auto generation = path_id(req.matches[2]), index = path_id(req.matches[3]);
               auto chunk = generation && index ? c.store.checkpoint_chunk(job->id, *generation, *index) : std::nullopt;
               if (!chunk)
                 return error(res, 404, "not_found",
                              "job " + std::to_string(job->id) + " has no checkpoint chunk " + req.matches[2] + "/" +
                                  req.matches[3] + " (replaced by a newer checkpoint?)");
               res.set_content(std::move(*chunk), "application/octet-stream");
             });

  // The curve's header; with resume_rows, a check that the store holds exactly the rows the checkpoint follows.
  router.post(R"(/v1/worker/jobs/(\d+)/begin)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    if (!still_running(*job, res)) return;
    const json body = json::parse(req.body, nullptr, false);
    if (!body.is_object() || !body.contains("header") || !body["header"].is_string())
      return error(res, 400, "invalid_value", "expected {\"header\": CSV header line, \"resume_rows\": n or null}",
                   "header");
    const std::string header = body["header"].get<std::string>();
    if (body.contains("resume_rows") && body["resume_rows"].is_number_unsigned()) {
      const std::size_t rows = body["resume_rows"].get<std::size_t>();
      if (!api::resumed_curve(c.store.live_curve_csv(job->id).value_or(header), rows)) {
        c.store.discard_partial_results(job->id);
        return error(
            res, 409, "cannot_resume",
            "the store does not hold the " + std::to_string(rows) + " rows the checkpoint follows: start afresh");
      }
      return reply(res, 200, {{"resume", true}});
    }
    c.store.start_curve(job->id, header);
    reply(res, 200, {{"resume", false}});
  });

  // Rows and snapshots since the last batch, and the progress; the answer says whether a cancel was asked.
  router.post(R"(/v1/worker/jobs/(\d+)/results)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    if (!still_running(*job, res)) return;
    const json body = json::parse(req.body, nullptr, false);
    std::vector<std::string> lines, values;
    std::vector<JobStore::SnapshotBlob> snapshots;
    std::size_t first = 0;
    double progress = 0, eta = -1;
    try {
      first = body.at("first_index").get<std::size_t>();
      lines = body.at("lines").get<std::vector<std::string>>();
      // Each row's values as its line reads them (api::curve_row_values); a worker may leave them out.
      if (body.contains("values")) values = body.at("values").get<std::vector<std::string>>();
      if (!values.empty() && values.size() != lines.size())
        throw std::invalid_argument("'values' must have one entry per line");
      for (const json& s : body.at("snapshots"))
        snapshots.push_back({s.at("index").get<int>(), s.at("strain").get<double>(), s.at("data").get<std::string>()});
      progress = body.at("progress").get<double>();
      eta = body.value("eta_seconds", -1.0);
    } catch (const std::exception& e) {
      return error(res, 400, "invalid_value", std::string("malformed results batch: ") + e.what(), "results");
    }
    std::vector<api::StoredRow> rows;
    for (std::size_t k = 0; k < lines.size(); ++k) rows.push_back({lines[k], values.empty() ? "" : values[k]});
    if (!rows.empty() || !snapshots.empty()) c.store.append_results(job->id, first, rows, snapshots);
    c.store.set_progress(job->id, progress, eta);
    reply(res, 200, {{"cancel", c.store.cancel_requested(job->id)}});
  });

  // A checkpoint, sent in chunks beside the stored one: a generation for it, its chunks (at most
  // CheckpointWriter::kChunkBytes each, in order), then the commit, which checks the whole (its frame and
  // checksum: a torn upload is refused, not stored) and makes it the job's with the rows it follows.
  router.post(R"(/v1/worker/jobs/(\d+)/checkpoint/begin)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    if (!still_running(*job, res)) return;
    reply(res, 200, {{"generation", c.store.begin_checkpoint(job->id)}});
  });
  router.post(R"(/v1/worker/jobs/(\d+)/checkpoint/(\d+)/(\d+))", {},
              [c](const http::Request& req, http::Response& res) {
                const auto job = worker_job(c, req, res);
                if (!job) return;
                if (!still_running(*job, res)) return;
                const auto generation = path_id(req.matches[2]), index = path_id(req.matches[3]);
                if (!generation || !index) return error(res, 400, "invalid_value", "bad chunk path", "chunk");
                if (req.body.empty() || req.body.size() > CheckpointWriter::kChunkBytes)
                  return error(res, 400, "invalid_value",
                               "a checkpoint chunk holds 1 to " + std::to_string(CheckpointWriter::kChunkBytes) +
                                   " bytes, not " + std::to_string(req.body.size()),
                               "chunk");
                if (!c.store.put_checkpoint_chunk(job->id, *generation, *index, req.body.data(), req.body.size()))
                  return error(res, 409, "wrong_state",
                               "no checkpoint " + req.matches[2] + " of job " + req.matches[1] +
                                   " is being written (a newer one began, or the daemon restarted): begin again",
                               "generation");
                reply(res, 200, {{"stored", true}});
              });
  router.post(
      R"(/v1/worker/jobs/(\d+)/checkpoint)", {"generation", "chunks", "bytes", "rows", "snapshots", "engine_version"},
      [c](const http::Request& req, http::Response& res) {
        const auto job = worker_job(c, req, res);
        if (!job) return;
        if (!still_running(*job, res)) return;
        long generation = -1, chunks = -1, bytes = -1, rows = -1, snapshots = -1;
        if (!query_int(req, res, "generation", 1, 1L << 50, generation) ||
            !query_int(req, res, "chunks", 1, 1L << 30, chunks) || !query_int(req, res, "bytes", 1, 1L << 50, bytes) ||
            !query_int(req, res, "rows", 0, 1L << 40, rows) || !query_int(req, res, "snapshots", 0, 1L << 20, snapshots))
          return;
        if (generation < 0 || chunks < 0 || bytes < 0 || rows < 0 || snapshots < 0)
          return error(res, 400, "missing", "'generation', 'chunks', 'bytes', 'rows' and 'snapshots' are required",
                       "generation");
        const std::string version = req.has_param("engine_version") ? req.get_param_value("engine_version") : "";
        const JobStore::Checkpoint cp{generation, chunks, bytes, rows, snapshots, version};
        try {
          verify_checkpoint(stored_checkpoint_source(c.store, job->id, cp));
        } catch (const CheckpointError& e) {
          c.store.end_checkpoint_write(job->id, generation);
          return error(res, 400, "invalid_value", std::string("unreadable checkpoint: ") + e.what(), "checkpoint");
        }
        c.store.append_results(job->id, std::size_t(rows), {}, {}, &cp);
        c.store.end_checkpoint_write(job->id, generation);
        reply(res, 200, {{"stored", true}});
        c.store.drop_checkpoint_garbage(std::size_t(-1));  // the previous checkpoint's chunks
      });

  // How the run ended: succeeded (with its summary; the curve is the rows sent), failed, cancelled, or
  // interrupted (a signal: the time limit is near, or Slurm stops it), which the daemon turns into a
  // cancel if one was asked, and otherwise into a requeue that resumes from the last checkpoint.
  router.post(R"(/v1/worker/jobs/(\d+)/end)", {}, [c](const http::Request& req, http::Response& res) {
    const auto job = worker_job(c, req, res);
    if (!job) return;
    const json body = json::parse(req.body, nullptr, false);
    const std::string outcome = text(body, "outcome", "");
    const std::int64_t id = job->id;
    if (outcome == "succeeded") {
      if (!body.contains("summary") || !body["summary"].is_object())
        return error(res, 400, "invalid_value", "a succeeded run sends its summary", "summary");
      const std::string csv = c.store.live_curve_csv(id).value_or("");
      const auto rows = c.store.live_rows(id);
      const json curve = rows ? api::curve_rows_to_json(rows->first, rows->second) : api::curve_csv_to_json(csv);
      if (c.store.succeed(id, body["summary"].dump(), csv, curve.dump()) || job->status == JobStatus::succeeded)
        return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::succeeded)}});
    } else if (outcome == "failed") {
      if (c.store.fail(id, text(body, "error", "the worker failed")) || job->status == JobStatus::failed)
        return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::failed)}});
    } else if (outcome == "cancelled") {
      if (c.store.mark_cancelled(id) || job->status == JobStatus::cancelled)
        return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::cancelled)}});
    } else if (outcome == "interrupted") {
      if (job->cancel_requested || job->status == JobStatus::cancelled) {
        c.store.mark_cancelled(id);
        return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::cancelled)}});
      }
      if (job->status == JobStatus::running) {
        switch (c.store.requeue_for_cluster(id, text(body, "reason", "its worker was interrupted"))) {
          case JobStore::Requeue::requeued:
            c.executor.notify();
            return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::queued)}});
          case JobStore::Requeue::cancelled:
            return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::cancelled)}});
          case JobStore::Requeue::failed:
            return reply(res, 200, {{"id", id}, {"status", api::status_name(JobStatus::failed)}});
          case JobStore::Requeue::not_active: break;
        }
      }
    } else {
      return error(res, 400, "invalid_value", "'outcome' must be succeeded, failed, cancelled or interrupted",
                   "outcome");
    }
    const auto now = c.store.get(id);
    error(res, 409, "wrong_state",
          "job " + std::to_string(id) + " is " + (now ? api::status_name(now->status) : "gone"));
  });
}

}  // namespace granulab::server
