#include "server/worker_pool.h"

#include <algorithm>

#include <omp.h>

#include <chrono>
#include <optional>

#include <spdlog/spdlog.h>

#include "api/engine_version.h"
#include "api/runner.h"
#include "engine/core/checkpoint.h"
#include "server/resume_point.h"
#include "server/store/sqlite.h"
#include "server/store_sink.h"

namespace granulab::server {

WorkerPool::WorkerPool(JobStore& store, int workers, int threads_per_job, double progress_seconds)
    : store_(store), workers_(workers), threads_per_job_(threads_per_job), progress_seconds_(progress_seconds) {}

WorkerPool::~WorkerPool() { stop(); }

void WorkerPool::start() {
  stopping_ = false;
  for (int k = 0; k < workers_; ++k) threads_.emplace_back([this] { work(); });
}

void WorkerPool::notify() { wake_.notify_one(); }

void WorkerPool::stop() {
  stopping_ = true;
  wake_.notify_all();
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
}

void WorkerPool::work() {
  // The engine's thread count is per calling thread in OpenMP: set once for this worker.
  omp_set_num_threads(threads_per_job_);
  // A store that cannot be claimed from (a full disk, the file gone) is tried again every 5 s, for as long as
  // it takes; the log says so at the first failure, then every 10 minutes, and when it works again.
  using Clock = std::chrono::steady_clock;
  std::optional<Clock::time_point> failing_since;
  Clock::time_point last_said{};
  long failures = 0;
  while (!stopping_) {
    std::optional<JobRecord> job;
    bool store_failed = false;
    try {
      job = store_.claim_next(max_running_per_owner_);
      if (failing_since)
        spdlog::info("the store takes claims again, after {} failed attempts over {:.0f} s", failures,
                     std::chrono::duration<double>(Clock::now() - *failing_since).count());
      failing_since.reset();
      failures = 0;
    } catch (const std::exception& e) {  // e.g. disk full or the file gone: retry, never crash
      store_failed = true;
      ++failures;
      const auto now = Clock::now();
      if (!failing_since || now - last_said > std::chrono::minutes(10)) {
        spdlog::error("cannot take the next job from the store: {}; trying again every 5 s{}", e.what(),
                      failing_since ? " (" + std::to_string(failures) + " attempts so far)" : "");
        last_said = now;
      }
      if (!failing_since) failing_since = now;
    }
    if (!job) {
      std::unique_lock<std::mutex> lock(mutex_);
      // Wake on notify(), or poll now and then in case another process queued work.
      wake_.wait_for(lock, std::chrono::seconds(store_failed ? 5 : 1));
      continue;
    }
    ++running_;
    run_job(*job);
    --running_;
  }
}

void WorkerPool::run_job(const JobRecord& job) {
  spdlog::info("job {} started ({})", job.id, job.experiment);
  const auto start = std::chrono::steady_clock::now();
  std::optional<api::Resume> resume = resume_point(store_, job.id, api::engine_version());
  for (;;) {
    StoreSink sink(store_, job.id, stopping_, progress_seconds_, checkpoint_seconds_, api::engine_version());
    try {
      const api::Spec spec = api::parse_spec_text(job.spec_json);
      // The spec's run.threads when it asks for fewer than the worker's share (a small crystal runs faster
      // on one thread than two: each parallel region costs a wake-up); 0, or more, is the share.
      omp_set_num_threads(spec.threads > 0 ? std::min(spec.threads, threads_per_job_) : threads_per_job_);
      api::run(spec, sink, resume ? &*resume : nullptr);
      spdlog::info("job {} succeeded in {:.1f} s; results written in {} batches taking {:.3f} s", job.id,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), sink.flushes(),
                   sink.flush_seconds_total());
    } catch (const CheckpointError& e) {
      if (resume) {  // the checkpoint does not fit this spec or the stored results: once more, afresh
        spdlog::warn("job {}: cannot resume ({}); it starts afresh", job.id, e.what());
        resume.reset();
        continue;
      }
      record_end(job.id, [&] { store_.fail(job.id, e.what()); });
    } catch (const Interrupted&) {
      spdlog::warn("job {} interrupted by shutdown; it will be re-queued at the next start", job.id);
    } catch (const Cancelled&) {
      keep_partial_results(sink, job.id);
      record_end(job.id, [&] { store_.mark_cancelled(job.id); });
      spdlog::info("job {} cancelled", job.id);
    } catch (const sqlite::StoreFull& e) {
      const std::string reason = std::string("the server's storage is full (its disk, or --max-db-mb): ") + e.what() +
                                 "; what was stored before is kept";
      // On a full disk even the failure needs room in the log: the reserve file gives it, so the job ends
      // `failed` (its checkpoint dropped, not run again at the next start) rather than stay `running`.
      if (store_.release_reserve()) spdlog::warn("job {}: the store is full; its reserve file was released", job.id);
      record_end(job.id, [&] { store_.fail(job.id, reason); });
      spdlog::error("job {} failed: {}", job.id, reason);
    } catch (const std::exception& e) {
      keep_partial_results(sink, job.id);
      const std::string reason = e.what();
      record_end(job.id, [&] { store_.fail(job.id, reason); });
      spdlog::error("job {} failed: {}", job.id, reason);
    }
    // A finished job keeps no checkpoint: its chunks go now, a chunk per transaction.
    record_end(job.id, [&] { store_.drop_checkpoint_garbage(std::size_t(-1)); });
    return;
  }
}

void WorkerPool::record_end(std::int64_t job, const std::function<void()>& write) {
  // The store itself may be failing (disk full, file removed): the worker logs it and goes on; the job
  // stays `running` in the file and is re-queued at the next start, so nothing is silently lost.
  try {
    write();
  } catch (const std::exception& e) {
    spdlog::error("job {}: could not record how it ended: {}", job, e.what());
  }
}

void WorkerPool::keep_partial_results(StoreSink& sink, std::int64_t job) {
  try {
    sink.flush();
  } catch (const std::exception& e) {
    spdlog::error("job {}: could not store its last results: {}", job, e.what());
  }
}

}  // namespace granulab::server
