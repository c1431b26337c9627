#include "server/slurm/slurm_executor.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include <spdlog/spdlog.h>

#include "api/spec.h"

namespace granulab::server::slurm {

using nlohmann::json;
using server::JobRecord;

namespace {

bool final_state(const std::string& s) {
  return s == "COMPLETED" || s == "FAILED" || s == "CANCELLED" || s == "TIMEOUT" || s == "NODE_FAIL" ||
         s == "OUT_OF_MEMORY" || s == "PREEMPTED" || s == "BOOT_FAIL" || s == "DEADLINE";
}

// A secret per job: 32 hex digits from the OS's entropy.
std::string fresh_secret() {
  std::random_device entropy;
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (int i = 0; i < 32; ++i) out += hex[entropy() & 15];
  return out;
}

// Slurm job names: letters, digits and -_. only, short.
std::string name_part(const std::string& label) {
  std::string out;
  for (const char c : label) {
    if (out.size() >= 40) break;
    out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
  }
  return out;
}

// The batch script: picks this task's job and secret from GRANULAB_WORKER_JOBS ("id:secret,..." by array
// index) and runs the worker under srun, so that Slurm's USR1 warning reaches it.
const char* kScript = R"(#!/bin/bash
# A granulabd job (or a sweep's jobs as an array): the worker fetches the spec and reports to the daemon.
set -u
IFS=, read -ra entries <<< "$GRANULAB_WORKER_JOBS"
entry=${entries[${SLURM_ARRAY_TASK_ID:-0}]}
export GRANULAB_WORKER_TOKEN=${entry#*:}
exec srun --ntasks=1 --cpus-per-task="$GRANULAB_CPUS" "$GRANULAB_WORKER_BINARY" worker \
  --server "$GRANULAB_SERVER" --job "${entry%%:*}"
)";

}  // namespace

SlurmExecutor::SlurmExecutor(JobStore& store, ExecutorOptions options)
    : store_(store), options_(std::move(options)), rest_(options_.rest) {
  if (::access(options_.worker_binary.c_str(), X_OK) != 0)
    throw std::invalid_argument("the worker binary '" + options_.worker_binary +
                                "' is not executable here (the nodes run it from the same path)");
  cluster_ = rest_.check();
}

SlurmExecutor::~SlurmExecutor() { stop(); }

void SlurmExecutor::start() {
  stopping_ = false;
  thread_ = std::thread([this] { work(); });
}

void SlurmExecutor::stop() {
  stopping_ = true;
  notify();
  if (thread_.joinable()) thread_.join();
}

void SlurmExecutor::notify() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    woken_ = true;
  }
  wake_.notify_one();
}

void SlurmExecutor::cancel_requested(std::int64_t) { notify(); }

void SlurmExecutor::work() {
  // A step that fails (slurmrestd away, the store failing) is logged, once a minute for the same message,
  // and tried again at the next poll: nothing leaves this thread.
  auto last_error = std::chrono::steady_clock::time_point();
  std::string last_message;
  while (!stopping_) {
    for (auto step : {&SlurmExecutor::submit_queued, &SlurmExecutor::follow}) {
      try {
        (this->*step)();
      } catch (const std::exception& e) {
        const auto now = std::chrono::steady_clock::now();
        if (e.what() != last_message || now - last_error > std::chrono::minutes(1))
          spdlog::error("Slurm executor: {}", e.what());
        last_error = now, last_message = e.what();
      } catch (...) {
        spdlog::error("Slurm executor: an unknown error; trying again");
      }
    }
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait_for(lock, std::chrono::duration<double>(options_.poll_seconds), [this] { return woken_; });
    woken_ = false;
  }
}

int SlurmExecutor::time_limit_minutes(const JobRecord& job, int threads) const {
  double seconds = 3600;  // when the spec cannot be read (it was validated on submission)
  try {
    const api::Spec spec = api::parse_spec_text(job.spec_json);
    seconds = spec.experiment->workload().sphere_steps() / (5e7 * std::max(1, threads));
  } catch (const std::exception&) {}
  const double minutes = std::ceil(3 * seconds / 60) + 5;
  return int(std::clamp(minutes, 1.0, double(options_.max_time_limit_minutes)));
}

void SlurmExecutor::submit_queued() {
  const std::vector<JobRecord> queued = store_.unsubmitted(200);
  // Neighbours in the queue from one sweep with the same resources go as one array.
  struct Batch {
    std::vector<JobRecord> jobs;
    int threads = 1, minutes = 1;
  };
  std::vector<Batch> batches;
  for (const JobRecord& job : queued) {
    int threads = options_.threads_per_job;
    try {
      const int own = api::parse_spec_text(job.spec_json).threads;
      if (own > 0) threads = own;
    } catch (const std::exception&) {}
    const int minutes = time_limit_minutes(job, threads);
    if (!batches.empty() && job.sweep_id != 0 && batches.back().jobs.front().sweep_id == job.sweep_id &&
        batches.back().threads == threads && batches.back().minutes == minutes)
      batches.back().jobs.push_back(job);
    else batches.push_back({{job}, threads, minutes});
  }
  for (const Batch& batch : batches) {
    if (stopping_) return;
    std::string entries;
    for (const JobRecord& job : batch.jobs)
      entries +=
          (entries.empty() ? "" : ",") + std::to_string(job.id) + ":" + store_.worker_token(job.id, fresh_secret());
    const JobRecord& first = batch.jobs.front();
    const bool array = batch.jobs.size() > 1;
    const std::string name =
        array ? "granulab-sweep" + std::to_string(first.sweep_id) + "-jobs" + std::to_string(first.id) + "-" +
                    std::to_string(batch.jobs.back().id)
              : "granulab-" + std::to_string(first.id) + (first.label.empty() ? "" : "-" + name_part(first.label));
    json desc = {{"name", name},
                 {"current_working_directory", "/tmp"},
                 {"standard_output", options_.output},
                 {"standard_error", options_.output},
                 {"tasks", 1},
                 {"cpus_per_task", batch.threads},
                 {"time_limit", batch.minutes},
                 {"requeue", false},
                 {"environment",
                  {{"PATH", "/usr/local/bin:/usr/bin:/bin"},
                   {"GRANULAB_SERVER", options_.public_url},
                   {"GRANULAB_WORKER_BINARY", options_.worker_binary},
                   {"GRANULAB_WORKER_JOBS", entries},
                   // Slurm sets SLURM_CPUS_PER_TASK for sbatch --cpus-per-task, not for a REST submission.
                   {"GRANULAB_CPUS", std::to_string(batch.threads)}}}};
    if (!options_.worker_ca_file.empty()) desc["environment"]["GRANULAB_CA_FILE"] = options_.worker_ca_file;
    // The warning comes `signal_seconds` before the limit; for short limits, halfway through.
    desc["signal"] = "USR1@" + std::to_string(std::min(options_.signal_seconds, batch.minutes * 30));
    if (!options_.partition.empty()) desc["partition"] = options_.partition;
    if (array) desc["array"] = "0-" + std::to_string(batch.jobs.size() - 1);
    std::int64_t slurm_id = 0;
    try {
      slurm_id = rest_.submit(desc, kScript);
    } catch (const Refused& e) {  // Slurm will not take these jobs (a bad partition, too many CPUs): they fail
      for (const JobRecord& job : batch.jobs) store_.fail(job.id, e.what());
      spdlog::error("jobs {}..{}: {}", first.id, batch.jobs.back().id, e.what());
      continue;
    } catch (const Unreachable& e) {  // slurmrestd or slurmctld away, a policy limit: they wait, and say why
      for (const JobRecord& job : batch.jobs)
        store_.set_slurm_state(job.id, "", std::string("not submitted yet: ") + e.what(), false);
      throw;
    }
    // Every id first, then the cancels: a failing cancel must not leave the batch's later jobs unrecorded.
    std::vector<std::string> cancelled;
    for (std::size_t k = 0; k < batch.jobs.size(); ++k) {
      const std::string id = array ? std::to_string(slurm_id) + "_" + std::to_string(k) : std::to_string(slurm_id);
      if (!store_.set_slurm_job(batch.jobs[k].id, id)) cancelled.push_back(id);  // cancelled while being submitted
      spdlog::info("job {} submitted to Slurm as {} ({} CPU(s), time limit {} min)", batch.jobs[k].id, id,
                   batch.threads, batch.minutes);
    }
    for (const std::string& id : cancelled) {
      cancels_sent_.insert(id);
      rest_.cancel(id);
    }
  }
}

void SlurmExecutor::follow() {
  // One query per Slurm job id: an array's tasks all come with its master id.
  std::map<std::string, std::vector<JobRecord>> by_master;
  for (JobRecord& job : store_.on_cluster())
    by_master[job.slurm_job_id.substr(0, job.slurm_job_id.find('_'))].push_back(job);
  for (const auto& [master, jobs] : by_master) {
    if (stopping_) return;
    try {  // one Slurm job's trouble does not stop the others being followed
      const std::optional<std::vector<SlurmJob>> records = rest_.job(master);
      for (const JobRecord& job : jobs) {
        if (!records) {
          follow_one(job, nullptr);  // Slurm does not know it (any more)
          continue;
        }
        const std::size_t underscore = job.slurm_job_id.find('_');
        const SlurmJob* mine = nullptr;
        for (const SlurmJob& r : *records) {
          const bool match = underscore == std::string::npos
                                 ? r.array_job_id == 0 && std::to_string(r.job_id) == master
                                 : r.covers_task(std::stoll(job.slurm_job_id.substr(underscore + 1)));
          if (match) mine = &r;
        }
        // A task not listed (Slurm shortens a long list of pending tasks): no news this time.
        if (mine) follow_one(job, mine);
      }
    } catch (const std::exception& e) {
      spdlog::warn("Slurm job {}: {}", master, e.what());
    }
  }
}

void SlurmExecutor::follow_one(const JobRecord& listed, const SlurmJob* record) {
  // The list may be seconds old (a query per Slurm job): act on the job as it is now, on the same Slurm job.
  const std::optional<JobRecord> current = store_.get(listed.id);
  if (!current || current->slurm_job_id != listed.slurm_job_id) return;
  const JobRecord& job = *current;
  const std::string& slurm_id = job.slurm_job_id;
  if (!record) {
    store_.set_slurm_state(job.id, slurm_id, "UNKNOWN (Slurm no longer knows job " + slurm_id + ")", true);
    if (!api::is_finished(job.status))
      store_.fail(job.id, "Slurm no longer knows job " + slurm_id + " and its worker never reported how it ended");
    return;
  }
  const std::string state = record->state + (record->reason.empty() ? "" : " (" + record->reason + ")");
  const bool ended = final_state(record->state);
  if (!ended && (job.status == JobStatus::cancelled || job.cancel_requested) && !cancels_sent_.count(slurm_id)) {
    rest_.cancel(slurm_id);
    cancels_sent_.insert(slurm_id);
    spdlog::info("job {}: cancelled Slurm job {}", job.id, slurm_id);
  }
  if (state != job.slurm_state || ended) store_.set_slurm_state(job.id, slurm_id, state, ended);
  if (!ended) {
    if (record->state == "RUNNING" && job.status == JobStatus::queued) store_.mark_running(job.id, slurm_id);
    return;
  }
  // The Slurm job is over. A worker that reported its end has already settled the job.
  const std::optional<JobRecord> now = store_.get(job.id);
  if (!now || api::is_finished(now->status) || now->slurm_job_id != slurm_id) return;
  if (now->cancel_requested || record->state == "CANCELLED") {
    store_.mark_cancelled(job.id);
    store_.log_event(job.id, "cancelled", "Slurm job " + slurm_id + " was cancelled");
    return;
  }
  const bool lost = record->state == "TIMEOUT" || record->state == "NODE_FAIL" || record->state == "PREEMPTED";
  if (lost) {  // resumes from its last checkpoint, within the limit of Slurm jobs per job
    if (store_.requeue_for_cluster(job.id, "Slurm job " + slurm_id + " ended " + state) == JobStore::Requeue::requeued)
      notify();
    return;
  }
  const int code = record->exit_code >> 8, signal = record->exit_code & 0x7f;
  std::string reason = "Slurm job " + slurm_id + " ended " + state + ", exit code " + std::to_string(code) +
                       (signal ? ", signal " + std::to_string(signal) : "");
  if (record->state == "COMPLETED") reason += ": its worker ended without reporting a result";
  store_.fail(job.id, reason);
}

}  // namespace granulab::server::slurm
