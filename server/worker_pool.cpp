#include "server/worker_pool.h"

#include <omp.h>

#include <chrono>

#include <spdlog/spdlog.h>

#include "api/runner.h"

namespace granulab::server {

namespace {

struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted by shutdown") {}
};

}  // namespace

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
  while (!stopping_) {
    std::optional<JobRecord> job = store_.claim_next();
    if (!job) {
      std::unique_lock<std::mutex> lock(mutex_);
      // Wake on notify(), or poll now and then in case another process queued work.
      wake_.wait_for(lock, std::chrono::seconds(1));
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
  auto last_report = start;
  try {
    const api::Spec spec = api::parse_spec_text(job.spec_json);
    const api::RunOutput out = api::run_spec(spec, [&](double fraction) {
      if (stopping_) throw Interrupted();
      const auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last_report).count() < progress_seconds_) return true;
      last_report = now;
      const double elapsed = std::chrono::duration<double>(now - start).count();
      store_.set_progress(job.id, fraction, fraction > 0 ? elapsed * (1 - fraction) / fraction : -1);
      return !store_.cancel_requested(job.id);
    });
    for (std::size_t k = 0; k < out.snapshots.size(); ++k) {
      const std::string text = out.snapshots[k].second.dump();
      store_.add_snapshot(job.id, int(k), out.snapshots[k].first, std::vector<std::uint8_t>(text.begin(), text.end()));
    }
    store_.succeed(job.id, out.summary.dump(), out.curve_csv, api::curve_csv_to_json(out.curve_csv).dump());
    spdlog::info("job {} succeeded in {:.1f} s", job.id,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  } catch (const Interrupted&) {
    spdlog::warn("job {} interrupted by shutdown; it will be re-queued at the next start", job.id);
  } catch (const Cancelled&) {
    store_.mark_cancelled(job.id);
    spdlog::info("job {} cancelled", job.id);
  } catch (const std::exception& e) {
    store_.fail(job.id, e.what());
    spdlog::error("job {} failed: {}", job.id, e.what());
  }
}

}  // namespace granulab::server
