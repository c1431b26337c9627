#include "engine/core/checkpoint.h"

namespace granulab {

namespace {

constexpr char kMagic[8] = {'G', 'R', 'N', 'L', 'C', 'K', 'P', 'T'};
constexpr std::uint32_t kVersion =
    4;  // raise when any saved layout changes (3: stage times, shear history per component; 4: candidates per grain pair)

// FNV-1a, 64 bits: catches truncation and bit rot; not a defence against tampering (the store is trusted).
std::uint64_t checksum(const char* data, std::size_t n) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<unsigned char>(data[i])) * 1099511628211ull;
  return h;
}

}  // namespace

CheckpointWriter::CheckpointWriter() {
  bytes_.append(kMagic, sizeof kMagic);
  value(kVersion);
}

void CheckpointWriter::section(const char* name) { text(name); }

void CheckpointWriter::text(const std::string& s) {
  value(std::uint64_t(s.size()));
  bytes_ += s;
}

std::string CheckpointWriter::finish() const {
  std::string out = bytes_;
  const std::uint64_t sum = checksum(out.data(), out.size());
  out.append(reinterpret_cast<const char*>(&sum), sizeof sum);
  return out;
}

CheckpointReader::CheckpointReader(const std::string& checkpoint) : bytes_(checkpoint) {
  if (bytes_.size() < sizeof kMagic + sizeof kVersion + 8 || std::memcmp(bytes_.data(), kMagic, sizeof kMagic) != 0)
    throw CheckpointError("not a granulab checkpoint");
  end_ = bytes_.size() - 8;
  std::uint64_t sum = 0;
  std::memcpy(&sum, bytes_.data() + end_, sizeof sum);
  if (sum != checksum(bytes_.data(), end_)) throw CheckpointError("checkpoint corrupt (checksum mismatch)");
  at_ = sizeof kMagic;
  const auto version = value<std::uint32_t>();
  if (version != kVersion)
    throw CheckpointError("checkpoint format " + std::to_string(version) + ", this build reads " +
                          std::to_string(kVersion));
}

void CheckpointReader::take(void* out, std::size_t n) {
  if (n > end_ - at_) throw CheckpointError("checkpoint truncated");
  std::memcpy(out, bytes_.data() + at_, n);
  at_ += n;
}

std::string CheckpointReader::text() {
  const auto n = value<std::uint64_t>();
  if (n > end_ - at_) throw CheckpointError("checkpoint truncated");
  std::string s(bytes_.data() + at_, n);
  at_ += n;
  return s;
}

void CheckpointReader::section(const char* name) {
  const std::string got = text();
  if (got != name) throw CheckpointError("checkpoint section '" + got + "' where '" + name + "' was expected");
}

void CheckpointReader::finish() const {
  if (at_ != end_) throw CheckpointError("checkpoint has " + std::to_string(end_ - at_) + " unread bytes");
}

}  // namespace granulab
