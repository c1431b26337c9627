#include "clients/cli/remote_sink.h"

#include <csignal>
#include <cstdlib>
#include <optional>
#include <thread>

#include <spdlog/spdlog.h>

#include "api/curve_format.h"
#include "api/engine_version.h"
#include "api/snapshot_files.h"
#include "engine/core/checkpoint.h"

// After the project headers: <resolv.h>, pulled in by httplib, defines a macro `_res` that breaks Eigen.
#include <httplib.h>

namespace granulab::cli {

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

const char* signal_reason(int sig) {
  return sig == SIGUSR1 ? "signal USR1: Slurm's warning before the time limit" : "signal TERM: Slurm stopped the job";
}

}  // namespace

DaemonLink::DaemonLink(const std::string& server, std::int64_t job, std::string token, std::string slurm_job_id,
                       double patience_seconds)
    : server_(server),
      job_(job),
      token_(std::move(token)),
      slurm_job_id_(std::move(slurm_job_id)),
      patience_(patience_seconds),
      http_(std::make_unique<httplib::Client>(server)) {
  if (!http_->is_valid()) throw std::invalid_argument("cannot use server URL '" + server + "'");
  // A daemon over HTTPS with a certificate of the lab's own: its CA, as the node sees it (granulabd passes
  // --worker-ca-file, or its own --tls-cert, in the Slurm job's environment).
  if (const char* ca = std::getenv("GRANULAB_CA_FILE"); ca && *ca) http_->set_ca_cert_path(ca);
  http_->set_connection_timeout(5);
  http_->set_read_timeout(120);  // a checkpoint of a large crystal takes a while to store
  http_->set_write_timeout(120);
}

DaemonLink::~DaemonLink() = default;

std::string DaemonLink::get(const std::string& suffix) { return request("GET", suffix, "", "", true); }

std::string DaemonLink::post(const std::string& suffix, const std::string& body, const std::string& content_type,
                             bool wait) {
  return request("POST", suffix, body, content_type, wait);
}

json DaemonLink::post_json(const std::string& suffix, const json& body, bool wait) {
  return json::parse(post(suffix, body.dump(), "application/json", wait));
}

std::string DaemonLink::request(const std::string& method, const std::string& suffix, const std::string& body,
                                const std::string& content_type, bool wait) {
  const std::string path = "/v1/worker/jobs/" + std::to_string(job_) + suffix;
  httplib::Headers headers = {{"X-Worker-Token", token_}};
  if (!slurm_job_id_.empty()) headers.emplace("X-Slurm-Job-Id", slurm_job_id_);
  double pause = 0.5;
  // While the daemon is away, a request that is not to wait does not even try more often than every
  // `retry_after_` (1 s, doubling to 30 s): an unreachable host would otherwise cost a connect timeout each.
  if (!wait && failing_since_ && seconds_since(last_attempt_) < retry_after_) throw Unavailable("the daemon is away");
  for (;;) {
    last_attempt_ = Clock::now();
    const httplib::Result r =
        method == "GET" ? http_->Get(path, headers) : http_->Post(path, headers, body, content_type);
    std::string problem;
    if (!r) {
      problem = "cannot reach " + server_ + " (" + httplib::to_string(r.error()) + ")";
    } else if (r->status < 400) {
      if (failing_since_) spdlog::info("the daemon answers again after {:.0f} s", seconds_since(*failing_since_));
      failing_since_.reset();
      retry_after_ = 1;
      return r->body;
    } else if ((r->status >= 500 && r->status != 507) || r->status == 429 || r->status == 408) {
      // (507: the daemon's store is full and has failed the job, so there is nothing to retry.)
      problem = method + " " + path + " answered " + std::to_string(r->status);
    } else {
      std::string code = "http_error", message = r->body;
      const json e = json::parse(r->body, nullptr, false);
      if (e.is_object() && e.contains("error") && e["error"].is_object()) {
        code = e["error"].value("code", code);
        message = e["error"].value("message", message);
      }
      throw Refused(r->status, code, method + " " + path + ": " + std::to_string(r->status) + " " + message);
    }
    // The daemon away (restarting, overloaded): keep trying for the patience.
    if (!failing_since_) {
      failing_since_ = Clock::now();
      spdlog::warn("{}; trying again for up to {:.0f} s", problem, patience_);
    }
    if (!wait) {  // the run goes on; patience is for the requests that wait
      retry_after_ = std::min(2 * retry_after_, 30.0);
      throw Unavailable(problem);
    }
    if (seconds_since(*failing_since_) > patience_)
      throw std::runtime_error(problem + ", for " + std::to_string(int(patience_)) + " s");
    std::this_thread::sleep_for(std::chrono::duration<double>(pause));
    pause = std::min(2 * pause, 5.0);
  }
}

RemoteSink::RemoteSink(DaemonLink& link, const std::atomic<int>& stop_signal, double flush_seconds,
                       double checkpoint_seconds, std::string engine_version)
    : link_(link),
      stop_signal_(stop_signal),
      flush_seconds_(flush_seconds),
      checkpoint_seconds_(checkpoint_seconds),
      engine_version_(std::move(engine_version)),
      start_(Clock::now()),
      last_flush_(start_),
      last_checkpoint_(start_) {}

void RemoteSink::begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) {
  columns_ = columns;
  json body = {{"header", api::curve_csv_header(columns)}, {"resume_rows", nullptr}};
  if (resume) body["resume_rows"] = resume->rows;
  try {
    link_.post_json("/begin", body);
  } catch (const Refused& e) {
    if (e.code == "cannot_resume") throw CheckpointError(e.what());  // the worker starts afresh
    throw;
  }
  rows_sent_ = resume ? resume->rows : 0;
}

void RemoteSink::curve_row(const std::vector<double>& values) {
  lines_.push_back(api::curve_csv_line(columns_, values));
  values_.push_back(api::curve_row_values(columns_, values));
}

void RemoteSink::snapshot(std::size_t index, const GrainSnapshot& s) {
  snapshots_.push_back({{"index", index}, {"strain", s.strain}, {"data", api::snapshot_json(s).dump()}});
}

bool RemoteSink::flush(bool wait) {
  const double elapsed = seconds_since(start_);
  json answer;
  try {
    answer = link_.post_json("/results",
                             {{"first_index", rows_sent_},
                              {"lines", lines_},
                              {"values", values_},
                              {"snapshots", snapshots_},
                              {"progress", fraction_},
                              {"eta_seconds", fraction_ > 0 ? elapsed * (1 - fraction_) / fraction_ : -1.0}},
                             wait);
  } catch (const Unavailable&) {
    last_flush_ = Clock::now();  // kept for the next flush; the run goes on
    return cancel_;
  }
  rows_sent_ += lines_.size();
  lines_.clear();
  values_.clear();
  snapshots_ = json::array();
  last_flush_ = Clock::now();
  cancel_ = cancel_ || answer.value("cancel", false);  // a flush for a checkpoint sees it too
  return cancel_;
}

void RemoteSink::interrupted() const { throw Interrupted(signal_reason(stop_signal_)); }

bool RemoteSink::progress(double fraction) {
  fraction_ = fraction;
  if (stop_signal_) {
    // As the daemon's own sink on shutdown: on to the next safe point for a checkpoint, then stop; without
    // checkpoints, or if none comes within half a second, stop here (the job resumes from the last one).
    if (checkpoint_seconds_ <= 0) interrupted();
    if (!stop_seen_) stop_seen_ = Clock::now();
    if (seconds_since(*stop_seen_) > 0.5) interrupted();
    return true;
  }
  if (cancel_) return false;
  if (seconds_since(last_flush_) < flush_seconds_) return true;
  return !flush(false);  // a daemon away does not hold the run up: the rows wait in memory
}

bool RemoteSink::checkpoint_due() {
  if (checkpoint_seconds_ <= 0) return false;
  return stop_signal_ || seconds_since(last_checkpoint_) >= checkpoint_seconds_;
}

void RemoteSink::checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) {
  // Before a stop (the time limit near) it waits for the daemon; otherwise a daemon away skips this one.
  const bool wait = stop_signal_ != 0;
  last_checkpoint_ = Clock::now();
  try {
    flush(wait);                                         // the rows and snapshots it follows are stored first
    if (!lines_.empty() || !snapshots_.empty()) return;  // they were not: no checkpoint this time
    const std::string generation =
        std::to_string(link_.post_json("/checkpoint/begin", json::object(), wait).at("generation").get<long long>());
    long long chunks = 0, bytes = 0;
    CheckpointWriter w([&](const char* data, std::size_t n) {
      link_.post("/checkpoint/" + generation + "/" + std::to_string(chunks), std::string(data, n),
                 "application/octet-stream", wait);
      ++chunks;
      bytes += static_cast<long long>(n);
    });
    content(w);
    w.finish();
    link_.post("/checkpoint?generation=" + generation + "&chunks=" + std::to_string(chunks) +
                   "&bytes=" + std::to_string(bytes) + "&rows=" + std::to_string(rows) +
                   "&snapshots=" + std::to_string(snapshots) +
                   "&engine_version=" + httplib::detail::encode_query_param(engine_version_),
               "", "application/octet-stream", wait);
  } catch (const Unavailable&) {
    return;
  } catch (const Refused& e) {
    if (e.status != 409) throw;
    spdlog::warn("checkpoint not stored ({}); the next one is due in {:.0f} s", e.what(), checkpoint_seconds_);
    return;
  }
  if (stop_signal_) interrupted();
}

api::Resume remote_checkpoint(DaemonLink& link) {
  const json meta = json::parse(link.get("/checkpoint"), nullptr, false);
  api::Resume r;
  try {
    r.rows = meta.at("rows").get<std::size_t>();
    r.snapshots = meta.at("snapshots").get<std::size_t>();
    const std::string chunks_path = "/checkpoint/" + std::to_string(meta.at("generation").get<long long>()) + "/";
    r.state = chunked_checkpoint_source(
        meta.at("bytes").get<std::uint64_t>(), meta.at("chunks").get<long long>(), [&link, chunks_path](std::int64_t k) {
          try {
            return link.get(chunks_path + std::to_string(k));
          } catch (const Refused&) {  // replaced meanwhile: the reader finds the checkpoint short
            return std::string();
          }
        });
  } catch (const json::exception& e) {
    throw CheckpointError(std::string("the daemon's description of the checkpoint is unusable: ") + e.what());
  }
  return r;
}

void RemoteSink::summary(const json& summary) {
  flush();
  link_.post_json("/end", {{"outcome", "succeeded"}, {"summary", summary}});
}

}  // namespace granulab::cli
