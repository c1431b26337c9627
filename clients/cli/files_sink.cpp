#include "clients/cli/files_sink.h"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <memory>
#include <stdexcept>

#include "api/curve_format.h"
#include "api/pictures/curve_pictures.h"
#include "api/snapshot_files.h"

namespace granulab::cli {

namespace fs = std::filesystem;

namespace {

// Peak resident memory of this process so far (bytes): the run's memory footprint.
long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024L;  // KiB on Linux
}

// A checkpoint file's head: the two counts and a check of them (the state carries its own checksum; a
// damaged count would trim the results at the wrong place).
constexpr std::size_t kHeadBytes = 3 * sizeof(std::uint64_t);

std::uint64_t counts_check(std::uint64_t rows, std::uint64_t snapshots) {
  return (rows * 1099511628211ull) ^ (snapshots + 1469598103934665603ull);
}

std::string checkpoint_head(std::size_t rows, std::size_t snapshots) {
  const std::uint64_t head[3] = {rows, snapshots, counts_check(rows, snapshots)};
  return std::string(reinterpret_cast<const char*>(head), sizeof head);
}

}  // namespace

api::Resume read_checkpoint_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t head[3] = {0, 0, 0};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  if (!in || fs::file_size(path) < kHeadBytes) throw CheckpointError("checkpoint truncated");
  if (head[2] != counts_check(head[0], head[1]))
    throw CheckpointError("checkpoint corrupt (its row and snapshot counts)");
  api::Resume r;
  r.rows = std::size_t(head[0]);
  r.snapshots = std::size_t(head[1]);
  r.state.size = fs::file_size(path) - kHeadBytes;
  r.state.open = [path]() -> CheckpointSource::ReadFn {
    auto file = std::make_shared<std::ifstream>(path, std::ios::binary);
    file->seekg(std::streamoff(kHeadBytes));
    return [file](char* data, std::size_t n) {
      file->read(data, std::streamsize(n));
      return std::size_t(file->gcount());
    };
  };
  verify_checkpoint(r.state);  // before anything is trimmed
  return r;
}

void write_file(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  fs::rename(tmp, path);
}

FilesSink::FilesSink(const fs::path& dir, ProgressFn progress, fs::path checkpoint_file, double checkpoint_seconds)
    : dir_(dir),
      progress_(std::move(progress)),
      checkpoint_file_(std::move(checkpoint_file)),
      checkpoint_seconds_(checkpoint_seconds),
      last_checkpoint_(std::chrono::steady_clock::now()) {
  fs::create_directories(dir_ / "snapshots");
  fs::remove(dir_ / "summary.json");
  if (!checkpoint_file_.empty()) fs::create_directories(checkpoint_file_.parent_path());
}

void FilesSink::begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) {
  columns_ = columns;
  const fs::path path = dir_ / "curve.csv";
  if (resume) {
    // Keep the header and the rows up to the checkpoint, and the snapshots taken before it.
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto kept = api::resumed_curve(text, resume->rows);
    if (text.rfind(api::curve_csv_header(columns_), 0) != 0 || !kept)
      throw std::runtime_error("'" + path.string() + "' does not hold the " + std::to_string(resume->rows) +
                               " curve rows the checkpoint follows: resume into the --out of the interrupted run");
    write_file(path, *kept);
    for (const auto& entry : fs::directory_iterator(dir_ / "snapshots")) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("snapshot_", 0) != 0) continue;
      const std::size_t k = std::strtoul(name.c_str() + 9, nullptr, 10);
      if (k >= resume->snapshots) fs::remove(entry.path());
    }
    curve_.open(path, std::ios::app | std::ios::binary);
    if (!curve_) throw std::runtime_error("cannot write '" + path.string() + "'");
    return;
  }
  curve_.open(path, std::ios::trunc | std::ios::binary);
  if (!curve_) throw std::runtime_error("cannot write '" + path.string() + "'");
  curve_ << api::curve_csv_header(columns_) << std::flush;
}

bool FilesSink::checkpoint_due() {
  return !checkpoint_file_.empty() && checkpoint_seconds_ > 0 &&  // 0 = never, as for granulabd
         std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_).count() >=
             checkpoint_seconds_;
}

void FilesSink::checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) {
  // curve.csv and the snapshots are already on disk up to here (flushed as made): the checkpoint follows.
  const fs::path tmp = checkpoint_file_.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << checkpoint_head(rows, snapshots);
    CheckpointWriter w([&out](const char* data, std::size_t n) { out.write(data, std::streamsize(n)); });
    content(w);
    w.finish();
    out.flush();
    if (!out) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  fs::rename(tmp, checkpoint_file_);  // a crash before this leaves the previous checkpoint
  last_checkpoint_ = std::chrono::steady_clock::now();
}

void FilesSink::curve_row(const std::vector<double>& values) {
  curve_ << api::curve_csv_line(columns_, values) << std::flush;
}

void FilesSink::snapshot(std::size_t k, const GrainSnapshot& s) {
  for (const api::SnapshotFile& f : api::snapshot_files(k, s)) write_file(dir_ / f.name, f.text);
}

void FilesSink::summary(const nlohmann::json& summary) {
  curve_.close();
  nlohmann::json s = summary;
  s["peak_rss_bytes"] = peak_rss_bytes();
  // The curve as the server draws it (curve.svg), before the summary that marks the run finished.
  const nlohmann::json spec = s.contains("spec") ? s["spec"] : nlohmann::json::object();
  std::ifstream csv(dir_ / "curve.csv", std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  write_file(dir_ / "curve.svg",
             pictures::line_plot_svg(pictures::job_curve_plot(spec, api::curve_csv_to_json(text), s)));
  write_file(dir_ / "summary.json", s.dump(2) + "\n");
  if (!checkpoint_file_.empty()) fs::remove(checkpoint_file_);  // a finished run is not resumed
}

}  // namespace granulab::cli
