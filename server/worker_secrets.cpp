#include "server/worker_secrets.h"

#include "server/http/replies.h"

namespace granulab::server {

bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

WorkerSecrets::WorkerSecrets(JobStore& store) {
  for (const auto& [job, secret] : store.worker_secrets()) secrets_[job] = secret;  // jobs on a cluster
}

bool WorkerSecrets::may_send(const std::string& target, const std::string& token) const {
  static const std::string prefix = "/v1/worker/jobs/";
  if (target.compare(0, prefix.size(), prefix) != 0) return false;
  const std::size_t end = target.find_first_not_of("0123456789", prefix.size());
  const auto id =
      http::path_id(target.substr(prefix.size(), end == std::string::npos ? std::string::npos : end - prefix.size()));
  if (!id) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = secrets_.find(*id);
  return it != secrets_.end() && same_secret(it->second, token);
}

void WorkerSecrets::remember(std::int64_t job, const std::string& secret) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (secrets_.size() > 100000) secrets_.clear();  // bounded: finished jobs' secrets go
  secrets_[job] = secret;
}

}  // namespace granulab::server
