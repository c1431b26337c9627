// The bytes of a checkpoint: a running experiment's full state, written so that a run resumed from it
// continues bit for bit as if never stopped (docs/architecture.md, "Checkpoints"). Values are written
// as their exact bytes (doubles never pass through text), in named sections that the reader checks, and
// the whole is framed by a magic, a format version and a checksum: a truncated, corrupted or foreign
// file is refused with a message, never half-read.
//
// Both directions stream: the writer hands its bytes on in chunks of at most `chunk_bytes` (16 MB) as it
// goes, and the reader pulls them from a source, so a checkpoint of a 5e7-sphere crystal (~14 GB) never
// exists whole in memory. What a checkpoint costs beyond the run's own state is one chunk each way.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
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

/// Where a checkpoint's bytes go, in order: one call per chunk (at most the writer's chunk_bytes).
using CheckpointChunkFn = std::function<void(const char* data, std::size_t size)>;

/// A checkpoint's bytes, readable from the start as often as asked. `open` starts a pass: each call of
/// the function it returns fills up to `size` bytes at `data` and says how many (0 only at the end).
struct CheckpointSource {
  using ReadFn = std::function<std::size_t(char* data, std::size_t size)>;
  std::uint64_t size = 0;  ///< B, in all
  std::function<ReadFn()> open;
};

/// A source over bytes in memory (tests, small states); it keeps its own copy.
CheckpointSource checkpoint_source(std::string bytes);

/// A source over `chunks` chunks of `size` bytes in all, each fetched when the reader reaches it (one in
/// memory at a time): `fetch(k)` gives chunk k, or an empty string if it is gone (read as a short file).
CheckpointSource chunked_checkpoint_source(std::uint64_t size, std::int64_t chunks,
                                           std::function<std::string(std::int64_t index)> fetch);

class CheckpointWriter {
 public:
  static constexpr std::size_t kChunkBytes = std::size_t(16) << 20;
  explicit CheckpointWriter(CheckpointChunkFn out, std::size_t chunk_bytes = kChunkBytes);
  /// A named section: the reader must ask for the same names in the same order.
  void section(const char* name);
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T> || std::is_same_v<T, Vec3> || std::is_same_v<T, Quat>);
    append(&v, sizeof v);
  }
  template <class T>
  void values(const std::vector<T>& v) {
    value(std::uint64_t(v.size()));
    if (!v.empty()) append(v.data(), v.size() * sizeof(T));
  }
  void text(const std::string& s);
  /// Ends the checkpoint: its checksum, then the last chunk out. Nothing may be written after.
  void finish();
  std::uint64_t size() const { return written_ + buffer_.size(); }  ///< B so far

 private:
  void append(const void* data, std::size_t n);
  void emit();
  CheckpointChunkFn out_;
  std::size_t chunk_bytes_;
  std::string buffer_;  // never more than chunk_bytes_
  std::uint64_t written_ = 0, sum_;
  bool finished_ = false;
};

/// What an experiment writes into a checkpoint (ResultSink::checkpoint): its state, through the writer.
using CheckpointContent = std::function<void(CheckpointWriter&)>;

/// A checkpoint whole, as one string: for tests and states known to be small.
std::string checkpoint_bytes(const CheckpointContent& content);

/// Reads the source once through: its frame and checksum, in O(chunk) memory. Throws CheckpointError.
void verify_checkpoint(const CheckpointSource& source);

class CheckpointReader {
 public:
  /// Checks the whole source first (verify_checkpoint), then reads it from the start: nothing of a torn
  /// or corrupted checkpoint reaches the state it restores. Throws CheckpointError.
  explicit CheckpointReader(const CheckpointSource& source);
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
  void finish();

 private:
  void take(void* out, std::size_t n);
  CheckpointSource::ReadFn read_;
  std::string buffer_;
  std::size_t buffered_at_ = 0;  // next unread byte of buffer_
  std::uint64_t at_ = 0, end_ = 0;
};

}  // namespace granulab
