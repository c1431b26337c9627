// The bytes of a checkpoint: a running experiment's full state, written so that a run resumed from it
// continues bit for bit as if never stopped (docs/architecture.md, "Checkpoints"). Values are written
// as their exact bytes (doubles never pass through text), in named sections that the reader checks, and
// the whole is framed by a magic, a format version and a checksum: a truncated, corrupted or foreign
// file is refused with a message, never half-read.
#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

/// A checkpoint that cannot be used: wrong magic or version, bad checksum, or a section out of place.
struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class CheckpointWriter {
 public:
  CheckpointWriter();
  /// A named section: the reader must ask for the same names in the same order.
  void section(const char* name);
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T> || std::is_same_v<T, Vec3> || std::is_same_v<T, Quat>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void values(const std::vector<T>& v) {
    value(std::uint64_t(v.size()));
    if (!v.empty()) bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s);
  /// The finished checkpoint (magic, version, payload, checksum).
  std::string finish() const;

 private:
  std::string bytes_;
};

class CheckpointReader {
 public:
  /// Checks the frame; throws CheckpointError.
  explicit CheckpointReader(const std::string& checkpoint);
  void section(const char* name);
  template <class T>
  T value() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  void value(T& v) {
    take(&v, sizeof v);
  }
  template <class T>
  void values(std::vector<T>& v) {
    const auto n = value<std::uint64_t>();
    if (n > (end_ - at_) / (sizeof(T) ? sizeof(T) : 1))
      throw CheckpointError("checkpoint truncated: an array is longer than the file");
    v.resize(n);
    if (n) take(v.data(), n * sizeof(T));
  }
  std::string text();
  /// Throws unless every byte was read.
  void finish() const;

 private:
  void take(void* out, std::size_t n);
  const std::string& bytes_;
  std::size_t at_ = 0, end_ = 0;
};

}  // namespace granulab
