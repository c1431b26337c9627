// Where a job that starts again resumes: after its daemon was stopped, its worker lost or its Slurm job
// requeued. One rule for the local pool and the cluster's workers.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "api/job_sink.h"
#include "server/store/job_store.h"

namespace granulab::server {

/// The job's stored checkpoint, with its stored results trimmed to it; none when there is no checkpoint,
/// when it is of another build than `engine_version` (the run's), or unreadable: the job then starts
/// afresh (its fresh start drops the old results). Never throws.
std::optional<api::Resume> resume_point(JobStore& store, std::int64_t job, const std::string& engine_version);

/// The stored checkpoint `cp` of `job` as a source that reads its chunks one at a time (one chunk in
/// memory); a chunk gone meanwhile reads as a truncated checkpoint.
CheckpointSource stored_checkpoint_source(JobStore& store, std::int64_t job, const JobStore::Checkpoint& cp);

}  // namespace granulab::server
