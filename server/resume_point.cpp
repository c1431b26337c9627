#include "server/resume_point.h"

#include <spdlog/spdlog.h>

#include "engine/core/checkpoint.h"

namespace granulab::server {

std::optional<api::Resume> resume_point(JobStore& store, std::int64_t job, const std::string& engine_version) {
  std::optional<JobStore::Checkpoint> cp;
  try {
    cp = store.checkpoint(job);
    if (!cp) return std::nullopt;
    if (cp->engine_version != engine_version) {
      spdlog::warn("job {}: its checkpoint is of another build ({}); it starts afresh", job, cp->engine_version);
      return std::nullopt;  // the fresh run's start_curve drops it with the old results
    }
    verify_checkpoint(stored_checkpoint_source(store, job, *cp));  // before any result is trimmed
    store.trim_results(job, cp->rows, cp->snapshots);
  } catch (const CheckpointError& e) {
    spdlog::warn("job {}: unusable checkpoint ({}); it starts afresh", job, e.what());
    return std::nullopt;
  } catch (const std::exception& e) {  // the store failing: a fresh run resets what it can
    spdlog::error("job {}: cannot read its checkpoint ({}); it starts afresh", job, e.what());
    return std::nullopt;
  }
  spdlog::info("job {} resumes from its checkpoint after {} curve rows", job, cp->rows);
  return api::Resume{stored_checkpoint_source(store, job, *cp), std::size_t(cp->rows), std::size_t(cp->snapshots)};
}

CheckpointSource stored_checkpoint_source(JobStore& store, std::int64_t job, const JobStore::Checkpoint& cp) {
  return chunked_checkpoint_source(std::uint64_t(cp.bytes), cp.chunks, [&store, job, cp](std::int64_t k) {
    return store.checkpoint_chunk(job, cp.generation, k).value_or(std::string());
  });
}

}  // namespace granulab::server
