// A job's status: the one place that spells the statuses (the store's column, the HTTP API's "status",
// the CLI's and the pictures' words). Life cycle in server/store/job_store.h.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace granulab::api {

enum class JobStatus { queued, running, succeeded, failed, cancelled };

inline constexpr std::array<JobStatus, 5> kJobStatuses = {JobStatus::queued, JobStatus::running, JobStatus::succeeded,
                                                          JobStatus::failed, JobStatus::cancelled};

/// "queued", "running", "succeeded", "failed", "cancelled".
constexpr const char* status_name(JobStatus s) {
  switch (s) {
    case JobStatus::queued: return "queued";
    case JobStatus::running: return "running";
    case JobStatus::succeeded: return "succeeded";
    case JobStatus::failed: return "failed";
    case JobStatus::cancelled: return "cancelled";
  }
  return "unknown";
}

inline std::optional<JobStatus> parse_job_status(std::string_view name) {
  for (JobStatus s : kJobStatuses)
    if (name == status_name(s)) return s;
  return std::nullopt;
}

/// "queued, running, succeeded, failed, cancelled": for messages that list the choices.
inline std::string job_status_names() {
  std::string out;
  for (JobStatus s : kJobStatuses) out += (out.empty() ? "" : ", ") + std::string(status_name(s));
  return out;
}

/// Succeeded, failed or cancelled: the job will not run again.
constexpr bool is_finished(JobStatus s) {
  return s == JobStatus::succeeded || s == JobStatus::failed || s == JobStatus::cancelled;
}
/// The same for a status as the API spells it (an unknown word is not finished).
inline bool is_finished(std::string_view name) {
  const auto s = parse_job_status(name);
  return s && is_finished(*s);
}

}  // namespace granulab::api
