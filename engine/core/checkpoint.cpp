#include "engine/core/checkpoint.h"

#include <algorithm>
#include <memory>

namespace granulab {

namespace {

constexpr char kMagic[8] = {'G', 'R', 'N', 'L', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t kVersion =
    9;  // raise when any saved layout changes (3: stage times, shear history per component; 4: candidates per grain
        // pair; 5: the energy balance; 6: stick-slip events; 7: candidates' bond flags; 8: the wrapped bag's flag;
        // 9: the open grain pairs, no stored energy per pair)
constexpr std::size_t kHead = sizeof kMagic + sizeof kVersion, kTrailer = sizeof(std::uint64_t);
constexpr std::size_t kReadBytes = std::size_t(1) << 20;  // what the reader asks of its source at a time

// FNV-1a, 64 bits: catches truncation and bit rot; not a defence against tampering (the store is trusted).
constexpr std::uint64_t kFnvStart = 1469598103934665603ull;
std::uint64_t fnv(std::uint64_t h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * 1099511628211ull;
  return h;
}

}  // namespace

CheckpointSource checkpoint_source(std::string bytes) {
  auto kept = std::make_shared<const std::string>(std::move(bytes));
  CheckpointSource source;
  source.size = kept->size();
  source.open = [kept]() -> CheckpointSource::ReadFn {
    auto at = std::make_shared<std::size_t>(0);
    return [kept, at](char* data, std::size_t size) {
      const std::size_t n = std::min(size, kept->size() - *at);
      std::memcpy(data, kept->data() + *at, n);
      *at += n;
      return n;
    };
  };
  return source;
}

CheckpointSource chunked_checkpoint_source(std::uint64_t size, std::int64_t chunks,
                                           std::function<std::string(std::int64_t index)> fetch) {
  CheckpointSource source;
  source.size = size;
  source.open = [chunks, fetch = std::move(fetch)]() -> CheckpointSource::ReadFn {
    struct Pass {
      std::string chunk;
      std::size_t at = 0;
      std::int64_t next = 0;
    };
    auto pass = std::make_shared<Pass>();
    return [chunks, fetch, pass](char* data, std::size_t n) -> std::size_t {
      while (pass->at == pass->chunk.size()) {
        if (pass->next >= chunks) return 0;
        pass->chunk = fetch(pass->next++);
        pass->at = 0;
        if (pass->chunk.empty()) return 0;
      }
      const std::size_t k = std::min(n, pass->chunk.size() - pass->at);
      std::memcpy(data, pass->chunk.data() + pass->at, k);
      pass->at += k;
      return k;
    };
  };
  return source;
}

// ------------------------------------------------------------------------------------------------ writer

CheckpointWriter::CheckpointWriter(CheckpointChunkFn out, std::size_t chunk_bytes)
    : out_(std::move(out)), chunk_bytes_(std::max<std::size_t>(chunk_bytes, 64)), sum_(kFnvStart) {
  buffer_.reserve(std::min(chunk_bytes_, kReadBytes));
  append(kMagic, sizeof kMagic);
  value(kVersion);
}

void CheckpointWriter::append(const void* data, std::size_t n) {
  if (finished_) throw std::logic_error("CheckpointWriter: written after finish()");
  const char* p = static_cast<const char*>(data);
  sum_ = fnv(sum_, p, n);
  while (n > 0) {
    const std::size_t k = std::min(n, chunk_bytes_ - buffer_.size());
    buffer_.append(p, k);
    p += k;
    n -= k;
    if (buffer_.size() == chunk_bytes_) emit();
  }
}

void CheckpointWriter::emit() {
  if (buffer_.empty()) return;
  out_(buffer_.data(), buffer_.size());
  written_ += buffer_.size();
  buffer_.clear();
}

void CheckpointWriter::section(const char* name) { text(name); }

void CheckpointWriter::text(const std::string& s) {
  value(std::uint64_t(s.size()));
  append(s.data(), s.size());
}

void CheckpointWriter::finish() {
  if (finished_) return;
  // The checksum is not part of what it sums: written past append().
  if (buffer_.size() + kTrailer > chunk_bytes_) emit();
  buffer_.append(reinterpret_cast<const char*>(&sum_), kTrailer);
  finished_ = true;
  emit();
}

std::string checkpoint_bytes(const CheckpointContent& content) {
  std::string out;
  CheckpointWriter w([&out](const char* data, std::size_t n) { out.append(data, n); });
  content(w);
  w.finish();
  return out;
}

// ------------------------------------------------------------------------------------------------ reader

void verify_checkpoint(const CheckpointSource& source) {
  if (source.size < kHead + kTrailer || !source.open) throw CheckpointError("not a granulab checkpoint");
  const std::uint64_t payload = source.size - kTrailer;  // magic, version and state: what the checksum sums
  const CheckpointSource::ReadFn read = source.open();
  std::string buffer(kReadBytes, '\0');
  std::uint64_t at = 0, sum = kFnvStart;
  char head[kHead], trailer[kTrailer];
  for (;;) {
    const std::size_t got = read(buffer.data(), buffer.size());
    if (got == 0) break;
    if (at + got > source.size) throw CheckpointError("checkpoint longer than its stored size");
    const std::uint64_t end = at + got;
    if (at < payload) sum = fnv(sum, buffer.data(), std::size_t(std::min(end, payload) - at));
    for (std::uint64_t i = at; i < std::min<std::uint64_t>(end, kHead); ++i) head[i] = buffer[i - at];
    for (std::uint64_t i = std::max(at, payload); i < end; ++i) trailer[i - payload] = buffer[i - at];
    at += got;
  }
  if (at < source.size) throw CheckpointError("checkpoint truncated");
  if (std::memcmp(head, kMagic, sizeof kMagic) != 0) throw CheckpointError("not a granulab checkpoint");
  std::uint64_t stored = 0;
  std::memcpy(&stored, trailer, sizeof stored);
  if (stored != sum) throw CheckpointError("checkpoint corrupt (checksum mismatch)");
}

CheckpointReader::CheckpointReader(const CheckpointSource& source) {
  verify_checkpoint(source);
  read_ = source.open();
  end_ = source.size - kTrailer;
  char magic[sizeof kMagic];
  take(magic, sizeof magic);
  const auto version = value<std::uint32_t>();
  if (version != kVersion)
    throw CheckpointError("checkpoint format " + std::to_string(version) + ", this build reads " +
                          std::to_string(kVersion));
}

void CheckpointReader::take(void* out, std::size_t n) {
  if (n > end_ - at_) throw CheckpointError("checkpoint truncated");
  char* p = static_cast<char*>(out);
  at_ += n;
  while (n > 0) {
    if (buffered_at_ == buffer_.size()) {
      if (n >= kReadBytes) {  // a large array: straight from the source into place
        const std::size_t got = read_(p, n);
        if (got == 0) throw CheckpointError("checkpoint truncated");
        p += got;
        n -= got;
        continue;
      }
      buffer_.resize(kReadBytes);
      const std::size_t got = read_(buffer_.data(), buffer_.size());
      if (got == 0) throw CheckpointError("checkpoint truncated");
      buffer_.resize(got);
      buffered_at_ = 0;
    }
    const std::size_t k = std::min(n, buffer_.size() - buffered_at_);
    std::memcpy(p, buffer_.data() + buffered_at_, k);
    buffered_at_ += k;
    p += k;
    n -= k;
  }
}

std::string CheckpointReader::text() {
  const auto n = value<std::uint64_t>();
  if (n > end_ - at_) throw CheckpointError("checkpoint truncated");
  std::string s(n, '\0');
  take(s.data(), n);
  return s;
}

void CheckpointReader::section(const char* name) {
  const std::string got = text();
  if (got != name) throw CheckpointError("checkpoint section '" + got + "' where '" + name + "' was expected");
}

void CheckpointReader::finish() {
  if (at_ != end_) throw CheckpointError("checkpoint has " + std::to_string(end_ - at_) + " unread bytes");
}

}  // namespace granulab
