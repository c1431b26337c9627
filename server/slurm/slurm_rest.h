// A client of slurmrestd's REST API, dialect openapi/v0.0.38 (Slurm 22.05; ../shared facts in
// docs/cluster.md): submit a batch job, read a job's state, cancel it. Every reply's `errors` are checked
// (a 200 can carry them) and its `meta` must name the dialect this client speaks, so a newer slurmrestd
// fails with a message saying so instead of being misread. Tokens: a fixed one (SLURM_JWT), or minted
// here for a few minutes at a time from the cluster's JWT key.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/http/client.h"

namespace granulab::server::slurm {

/// slurmrestd could not be reached, or answered something this client cannot use: try again later.
struct Unreachable : std::runtime_error {
  using std::runtime_error::runtime_error;
};
/// Slurm refused the request (its own message): trying again will not help.
struct Refused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// One entry of a job query: a job, an array task, or an array's tasks still pending together.
struct SlurmJob {
  std::int64_t job_id = 0;
  std::int64_t array_job_id = 0;  ///< 0 unless part of an array
  std::optional<std::int64_t> array_task_id;
  std::string array_task_string;  ///< pending tasks not yet split out, e.g. "1-3,5" (array_task_id empty)
  std::string state;              ///< PENDING, RUNNING, COMPLETED, FAILED, CANCELLED, TIMEOUT, ...
  std::string reason;             ///< Slurm's state_reason ("None" dropped)
  int exit_code = 0;              ///< the raw wait status (exit 3 reads 768)
  /// True if this record stands for task `task` of its array.
  bool covers_task(std::int64_t task) const;
};

struct RestOptions {
  std::string url;      ///< e.g. http://127.0.0.1:6820
  std::string user;     ///< X-SLURM-USER-NAME, and the tokens' `sun`
  std::string jwt_key;  ///< the key's bytes (mint tokens), or empty
  std::string jwt;      ///< a fixed token (SLURM_JWT), used when there is no key
};

class RestClient {
 public:
  explicit RestClient(RestOptions options);
  ~RestClient();
  /// Checks that slurmrestd answers in this client's dialect; returns "Slurm 22.05.8 (openapi/v0.0.38)".
  std::string check();
  /// Submits a batch job (`job` is the v0.0.38 job description); returns its id (an array's master id).
  /// Refused when Slurm turns down what the job asks for (partition, nodes, time limit, CPUs); Unreachable
  /// for everything that may pass (slurmrestd or slurmctld away, credentials, policy limits).
  std::int64_t submit(const nlohmann::json& job, const std::string& script);
  /// The records of a job id ("123": the job, or every task of array 123; "123_4": one task); nullopt when
  /// Slurm does not know it (any more).
  std::optional<std::vector<SlurmJob>> job(const std::string& id);
  /// Cancels a job or an array task ("123_4"); an id Slurm no longer knows is not an error.
  void cancel(const std::string& id);

 private:
  /// One request; the parsed reply, its `meta` and `errors` checked. `status` receives the HTTP status.
  nlohmann::json call(const std::string& method, const std::string& path, const std::string& body, int& status);
  std::string token();
  RestOptions options_;
  std::unique_ptr<http::Client> http_;
  std::mutex mutex_;  // one request at a time on the one connection
  std::string token_;
  std::chrono::steady_clock::time_point token_renew_;
};

/// The API path prefix of the dialect spoken here.
inline constexpr const char* kDialect = "v0.0.38";

}  // namespace granulab::server::slurm
