#include "server/admission.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <unistd.h>

#include "api/spec.h"
#include "api/summary_json.h"
#include "server/http/replies.h"
#include "server/speed_model.h"

namespace granulab::server {

using nlohmann::json;

namespace {

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  return text;
}

std::string number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

Admission::Admission(JobStore& store, const Executor& executor, AdmissionLimits limits,
                     const MachineSpeed* machine_speed)
    : store_(store), executor_(executor), limits_(limits), machine_speed_(machine_speed) {
  if (limits_.max_memory_bytes <= 0)
    limits_.max_memory_bytes = 0.5 * double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
}

std::string Admission::budget_problem(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const std::string size = number(w.spheres) + " spheres in " + number(w.grains) + " grains";
  if (w.peak_bytes() > limits_.max_memory_bytes)
    return "this job would need about " + gigabytes(w.peak_bytes()) + " of memory (" + size +
           "); the server's limit is " + gigabytes(limits_.max_memory_bytes) + " (max_memory)";
  if (w.sphere_steps() > limits_.max_sphere_steps)
    return "this job would take about " + number(w.sphere_steps()) + " sphere-steps (" + size + " x " +
           number(w.steps) + " steps); the server's limit is " + number(limits_.max_sphere_steps) +
           " (max_sphere_steps)";
  return "";
}

bool Admission::within_budget(const api::Spec& spec, http::Response& res) const {
  const std::string problem = budget_problem(spec);
  if (problem.empty()) return true;
  http::error(res, 400, "over_budget", problem);
  return false;
}

bool Admission::within_queue_quota(const User& who, std::size_t more, http::Response& res) const {
  if (limits_.max_queued_per_user <= 0) return true;
  const std::size_t queued = store_.count(JobStatus::queued, who.name);
  if (queued + more <= std::size_t(limits_.max_queued_per_user)) return true;
  http::error(res, 429, "quota",
              (who.name.empty() ? std::string("the server") : "user '" + who.name + "'") + " has " +
                  std::to_string(queued) + " queued jobs and asks for " + std::to_string(more) +
                  " more; the limit is " + std::to_string(limits_.max_queued_per_user) +
                  " (max_queued_per_user): wait for some to start or cancel some");
  return false;
}

namespace {

// What the store keeps of a run (B), upper bounds of what stored jobs measured (2026-12-02): each curve value
// is written as text up to four times (the live row's CSV line and JSON values, then the finished curve's
// CSV and JSON: 11-24 KB for 51-101 rows of 20-odd columns measured); a snapshot 388-407 B per grain
// (N_e = 3 to 6); a checkpoint 19-30 B per sphere at rest and about 274 B per sphere once loading has made
// its contacts (the audit at full size).
constexpr double kBytesPerCurveValue = 60;
constexpr double kBytesPerSnapshotGrain = 450;
constexpr double kBytesPerCheckpointSphere = 300;

std::string megabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  return text;
}

}  // namespace

double Admission::expected_store_bytes(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const double results = w.curve_rows * double(spec.experiment->curve_columns().size()) * kBytesPerCurveValue +
                         w.snapshots * w.grains * kBytesPerSnapshotGrain + 4096;
  const double checkpoints = executor_.checkpoint_seconds() > 0 ? 3 * kBytesPerCheckpointSphere * w.spheres : 0;
  return results + checkpoints;
}

bool Admission::within_storage(double bytes, http::Response& res) const {
  const JobStore::Space s = store_.space();
  if (!s.limited || s.committed + bytes <= s.room) return true;
  http::error(res, 507, "storage_full",
              "the store has " + megabytes(s.room) + " left (--max-db-mb or the disk, its write-ahead log counted); "
              "the jobs queued and running are expected to take " + megabytes(s.committed) + " of it and this " +
              "submission " + megabytes(bytes) + ": nothing was queued. Delete finished jobs, or ask the "
              "server's administrator for room");
  return false;
}

bool Admission::within_user_storage(const User& who, double bytes, http::Response& res) const {
  if (limits_.max_user_bytes <= 0) return true;
  const double held = store_.user_bytes(who.name);
  if (held + bytes <= limits_.max_user_bytes) return true;
  http::error(res, 507, "storage_quota",
              (who.name.empty() ? std::string("the server's jobs") : "user '" + who.name + "'") + " hold or may write " +
                  megabytes(held) + " and this submission " + megabytes(bytes) + "; the limit is " +
                  megabytes(limits_.max_user_bytes) + " a user (--max-user-mb): nothing was queued. Delete finished "
                  "jobs to make room");
  return false;
}

json Admission::cost_estimate(const api::Spec& spec) const {
  const Workload w = spec.experiment->workload();
  const std::string experiment = spec.normalized["experiment"].get<std::string>();
  // The threads it will run on: the executor's share, fewer when the spec asks (WorkerPool).
  const int threads = spec.threads > 0 ? std::min(spec.threads, executor_.threads_per_job()) : executor_.threads_per_job();
  // This server's own speed: its recent succeeded jobs' sizes, threads and sphere-steps per second.
  std::vector<MeasuredRun> history;
  for (const JobRecord& j : store_.list(JobStatus::succeeded, 50, 0, "")) {
    const json summary = json::parse(j.summary_json, nullptr, false);
    if (!summary.is_object()) continue;
    const auto number = [&](const char* key) {
      return summary.contains(key) && summary[key].is_number() ? summary[key].get<double>() : 0.0;
    };
    history.push_back({{j.experiment, number("spheres"), number("grains"), int(number("threads"))},
                       number("sphere_steps_per_second")});
  }
  const SpeedEstimate speed = estimate_speed({experiment, w.spheres, w.grains, threads}, history,
                                             machine_speed_ ? machine_speed_->probe() : 0);
  json phases = json::array();
  for (const WorkPhase& p : w.phases) phases.push_back({{"name", p.name}, {"steps", p.steps}});
  json out = {{"dry_run", true},
              {"experiment", experiment},
              {"spheres", std::llround(w.spheres)},  // counts, as integers
              {"grains", std::llround(w.grains)},
              {"steps", w.expected_steps()},
              {"phases", phases},
              {"max_steps", w.steps},
              {"sphere_steps", w.expected_sphere_steps()},
              {"memory_bytes", w.peak_bytes()},
              {"threads", threads},
              {"sphere_steps_per_second", speed.sphere_steps_per_second},
              {"rate_basis", speed.basis},
              {"expected_seconds", w.expected_sphere_steps() / speed.sphere_steps_per_second},
              {"queued_ahead", store_.count(JobStatus::queued)},
              {"units",
               {{"memory_bytes", "B"}, {"expected_seconds", "s"}, {"sphere_steps_per_second", "1/s"}}}};
  if (const json estimate = api::yield_estimate_json(*spec.experiment); !estimate.is_null())
    out["yield_estimate"] = estimate;
  if (const std::string problem = budget_problem(spec); !problem.empty()) out["over_budget"] = problem;
  return out;
}

}  // namespace granulab::server
