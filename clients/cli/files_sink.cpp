#include "clients/cli/files_sink.h"

#include <sys/resource.h>

#include <stdexcept>

#include "api/curve_format.h"
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

}  // namespace

void write_file(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  fs::rename(tmp, path);
}

FilesSink::FilesSink(const fs::path& dir, ProgressFn progress) : dir_(dir), progress_(std::move(progress)) {
  fs::create_directories(dir_ / "snapshots");
  fs::remove(dir_ / "summary.json");
}

void FilesSink::begin(const std::vector<CurveColumn>& columns) {
  columns_ = columns;
  curve_.open(dir_ / "curve.csv", std::ios::trunc | std::ios::binary);
  if (!curve_) throw std::runtime_error("cannot write '" + (dir_ / "curve.csv").string() + "'");
  curve_ << api::curve_csv_header(columns_) << std::flush;
}

void FilesSink::curve_row(const std::vector<double>& values) {
  curve_ << api::curve_csv_line(columns_, values) << std::flush;
}

void FilesSink::snapshot(std::size_t k, const GrainSnapshot& s) {
  const std::string stem = (dir_ / "snapshots" / ("snapshot_" + std::to_string(k))).string();
  write_file(stem + ".json", api::snapshot_json(s).dump() + "\n");
  write_file(stem + ".dump", api::snapshot_lammps_dump(s));
  write_file(stem + "_grains.vtk", api::snapshot_grains_vtk(s));
  write_file(stem + "_interfaces.vtk", api::snapshot_interfaces_vtk(s));
}

void FilesSink::summary(const nlohmann::json& summary) {
  curve_.close();
  nlohmann::json s = summary;
  s["peak_rss_bytes"] = peak_rss_bytes();
  write_file(dir_ / "summary.json", s.dump(2) + "\n");
}

}  // namespace granulab::cli
