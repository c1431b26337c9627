// One daemon per database: granulabd holds an exclusive lock on `<db>.lock` while it runs, so a second
// daemon started on the same file refuses to start instead of running the queued jobs a second time.
// The kernel drops the lock when the process dies, kill -9 included: a restart never finds a stale one.
#pragma once

#include <string>

namespace granulab::server {

class InstanceLock {
 public:
  /// Takes the lock or throws std::runtime_error naming the database and the holder's pid.
  explicit InstanceLock(const std::string& db_path);
  ~InstanceLock();
  InstanceLock(const InstanceLock&) = delete;
  InstanceLock& operator=(const InstanceLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace granulab::server
