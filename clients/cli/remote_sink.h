// The JobSink of `granulab worker`: a job running on a cluster node sends what it makes to the daemon that
// owns the job (server/worker_routes.cpp), as the daemon's own StoreSink would store it: curve rows and
// snapshots in batches at most every `flush_seconds` with the progress (whose answer carries a cancel
// request), checkpoints every `checkpoint_seconds`, the summary at the end. A daemon that does not answer
// (restarting, a network blip) does not hold the run up: rows and snapshots wait in memory for the next
// batch and checkpoints are skipped meanwhile; only the end (and a checkpoint before a stop) waits for it,
// up to `patience` seconds. Nothing is lost or stored twice: every request is idempotent on the daemon's side.
// A stop signal (SIGUSR1 from Slurm before the time limit, SIGTERM) makes the run store a checkpoint at
// its next safe point and end with Interrupted.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/job_sink.h"

namespace httplib {
class Client;
}

namespace granulab::cli {

/// The run stopped for a signal (its checkpoint, if one was due, is stored).
struct Interrupted : std::runtime_error {
  explicit Interrupted(const std::string& why) : std::runtime_error(why) {}
};

/// The daemon did not answer a request that was not to wait for it (see DaemonLink::request).
struct Unavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The daemon refused a request (4xx other than a retryable one): its status and message.
struct Refused : std::runtime_error {
  Refused(int status, const std::string& code, const std::string& message)
      : std::runtime_error(message), status(status), code(code) {}
  int status;
  std::string code;
};

/// One job's connection to its daemon: the worker routes with the job's secret, retried while the daemon
/// is away.
class DaemonLink {
 public:
  DaemonLink(const std::string& server, std::int64_t job, std::string token, std::string slurm_job_id,
             double patience_seconds);
  ~DaemonLink();
  /// GET/POST on /v1/worker/jobs/{job}{suffix}; the answer's body. Throws Refused on a 4xx, and
  /// std::runtime_error when the daemon stayed unreachable (or answered 5xx) for the whole patience;
  /// with `wait` false, Unavailable at once instead of retrying.
  std::string get(const std::string& suffix);
  std::string post(const std::string& suffix, const std::string& body, const std::string& content_type,
                   bool wait = true);
  nlohmann::json post_json(const std::string& suffix, const nlohmann::json& body, bool wait = true);
  std::int64_t job() const { return job_; }

 private:
  std::string request(const std::string& method, const std::string& suffix, const std::string& body,
                      const std::string& content_type, bool wait);
  std::string server_;
  std::int64_t job_;
  std::string token_, slurm_job_id_;
  double patience_;
  std::unique_ptr<httplib::Client> http_;
  std::optional<std::chrono::steady_clock::time_point> failing_since_;  ///< the daemon not answering since
  std::chrono::steady_clock::time_point last_attempt_;
  double retry_after_ = 1;  ///< s between attempts of requests that do not wait, while the daemon is away
};

/// The job's stored checkpoint, read from the daemon a chunk at a time as the run restores it (one chunk
/// in memory). Throws CheckpointError when its description is unusable, Refused without one.
api::Resume remote_checkpoint(DaemonLink& link);

class RemoteSink : public api::JobSink {
 public:
  /// `stop_signal`: set (to the signal's number) by the worker's handler.
  RemoteSink(DaemonLink& link, const std::atomic<int>& stop_signal, double flush_seconds, double checkpoint_seconds,
             std::string engine_version);
  void begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) override;
  void curve_row(const std::vector<double>& values) override;
  void snapshot(std::size_t index, const GrainSnapshot& s) override;
  bool progress(double fraction) override;
  bool checkpoint_due() override;
  /// Sends the state in chunks (begin, one POST per chunk, commit); a daemon away or a write it no
  /// longer takes skips this checkpoint, except before a stop, which waits for it.
  void checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) override;
  void summary(const nlohmann::json& summary) override;
  /// Sends what is buffered; true once the daemon has asked to stop (a cancel). With `wait` false and the
  /// daemon away, it stays buffered for the next flush.
  bool flush(bool wait = true);

 private:
  [[noreturn]] void interrupted() const;
  DaemonLink& link_;
  const std::atomic<int>& stop_signal_;
  double flush_seconds_, checkpoint_seconds_;
  std::string engine_version_;
  std::vector<CurveColumn> columns_;
  std::vector<std::string> lines_;   // not yet sent
  std::vector<std::string> values_;  // their values as the lines read them (api::curve_row_values)
  nlohmann::json snapshots_ = nlohmann::json::array();
  std::size_t rows_sent_ = 0;
  double fraction_ = 0;
  bool cancel_ = false;  ///< the daemon asked to stop
  std::chrono::steady_clock::time_point start_, last_flush_, last_checkpoint_;
  std::optional<std::chrono::steady_clock::time_point> stop_seen_;
};

}  // namespace granulab::cli
