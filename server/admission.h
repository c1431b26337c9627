// What a submission must pass before anything is queued (docs/api.md, "Budgets" and "Users"): the
// per-job budget against the experiment's workload estimate, the per-user queue quota, and the dry run's
// cost estimate at this server's recent speed.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "server/access.h"
#include "server/executor.h"
#include "server/http/message.h"
#include "server/machine_speed.h"
#include "server/store/job_store.h"

namespace granulab::api {
struct Spec;
}  // namespace granulab::api

namespace granulab::server {

struct AdmissionLimits {
  int max_queued_per_user = 1000;  ///< more queued jobs of one user get 429 (0 = no limit)
  double max_memory_bytes = 0;     ///< B, a job's estimated peak memory; 0 = half the machine's physical memory
  double max_sphere_steps = 4e12;  ///< spheres x time steps (under 12 h at the slowest full-size speed measured, 9.4e7/s)
  double max_user_bytes = 0;       ///< B one user's jobs may hold or be expected to write (JobStore::user_bytes); 0 = no limit
};

class Admission {
 public:
  Admission(JobStore& store, const Executor& executor, AdmissionLimits limits,
            const MachineSpeed* machine_speed = nullptr);

  /// Why the job is over the per-job budget (naming the limit and the estimate), or empty.
  std::string budget_problem(const api::Spec& spec) const;
  /// False (and a 400 naming the limit and the estimate) when the job is over the per-job budget.
  bool within_budget(const api::Spec& spec, http::Response& res) const;
  /// False (and a 429 naming the limit) when `who` may not queue `more` jobs.
  bool within_queue_quota(const User& who, std::size_t more, http::Response& res) const;
  /// B a job of `spec` is expected to store at most: its curve rows and snapshots as the store keeps
  /// them and, with checkpoints on, three of its checkpoints (the stored one, its replacement being
  /// written, and the write-ahead log's copy of it).
  double expected_store_bytes(const api::Spec& spec) const;
  /// False (and a 507 naming the room and what is asked) when the store cannot hold `bytes` more beside
  /// what the jobs queued and running are expected to store.
  bool within_storage(double bytes, http::Response& res) const;
  /// False (and a 507 `storage_quota` naming --max-user-mb, what `who` holds and what is asked) when `bytes`
  /// more would take `who` past the per-user limit.
  bool within_user_storage(const User& who, double bytes, http::Response& res) const;
  /// A dry run's answer: spheres, steps, memory and the expected wall time at this server's recent speed.
  nlohmann::json cost_estimate(const api::Spec& spec) const;

 private:
  JobStore& store_;
  const Executor& executor_;
  AdmissionLimits limits_;
  const MachineSpeed* machine_speed_;
};

}  // namespace granulab::server
