// The secrets of the jobs' workers (a job on a cluster presents its own in X-Worker-Token), as the
// connection loop needs them: it decides from a request's head whether a large body may follow, and its
// one thread never waits for the store (a large checkpoint may be being written). It knows the active
// jobs' secrets at start-up and those of every worker answered since (a worker's first request is small).
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

#include "server/store/job_store.h"

namespace granulab::server {

/// Compares in time independent of where they differ (no early exit: the time tells nothing of a guess).
bool same_secret(const std::string& a, const std::string& b);

class WorkerSecrets {
 public:
  /// Starts with the secrets of the store's queued and running jobs.
  explicit WorkerSecrets(JobStore& store);
  /// `target` is /v1/worker/jobs/<id>/... and `token` that job's secret.
  bool may_send(const std::string& target, const std::string& token) const;
  void remember(std::int64_t job, const std::string& secret);

 private:
  mutable std::mutex mutex_;
  std::unordered_map<std::int64_t, std::string> secrets_;  ///< job id -> its worker's secret, as seen
};

}  // namespace granulab::server
