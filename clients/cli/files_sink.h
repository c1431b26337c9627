// The files of `granulab run SPEC --out DIR` (docs/api.md), written as the run makes them so a killed
// run keeps what it computed: DIR/curve.csv grows a row at a time (flushed), each snapshot k is written
// when taken as snapshots/snapshot_k.json (compact, what the server stores), .dump (LAMMPS text dump,
// opens in OVITO), _grains.vtk and _interfaces.vtk (ParaView), _contacts.vtk and _contacts.dump (the contact
// network), _meshes.vtk (the grains' polyhedra), _dic.csv and _dic.vtk (the front face's DIC-like
// map, api/dic_files.h); summary.json, written last, marks a
// finished run. With a checkpoint file, the run's state is written there every `checkpoint_seconds`
// (atomically: a crash leaves the previous one), and a run resumed from it trims curve.csv and the
// snapshots back to the checkpoint and carries on.
#pragma once

#include <chrono>
#include <filesystem>
#include <fstream>
#include <vector>

#include "api/job_sink.h"

namespace granulab::cli {

class FilesSink : public api::JobSink {
 public:
  /// Creates DIR and DIR/snapshots; removes a summary.json left by an earlier run. `checkpoint_file`
  /// empty: no checkpoints.
  FilesSink(const std::filesystem::path& dir, ProgressFn progress, std::filesystem::path checkpoint_file = {},
            double checkpoint_seconds = 60);
  void begin(const std::vector<CurveColumn>& columns, const api::Resume* resume) override;
  bool checkpoint_due() override;
  /// Streams the state into CHECKPOINT.tmp after a head of the two counts, then renames it.
  void checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) override;
  void curve_row(const std::vector<double>& values) override;
  void snapshot(std::size_t index, const GrainSnapshot& s) override;
  bool progress(double fraction) override { return !progress_ || progress_(fraction); }
  /// Writes summary.json with the process's peak memory added.
  void summary(const nlohmann::json& summary) override;

 private:
  std::filesystem::path dir_;
  ProgressFn progress_;
  std::vector<CurveColumn> columns_;
  std::ofstream curve_;
  std::filesystem::path checkpoint_file_;
  double checkpoint_seconds_;
  std::chrono::steady_clock::time_point last_checkpoint_;
};

/// Writes to a temporary name and renames, so a crash never leaves a half-written file.
void write_file(const std::filesystem::path& path, const std::string& text);

/// A checkpoint file FilesSink wrote, its frame and checksum checked (CheckpointError); its state is read
/// from the file when the run restores it, never loaded whole.
api::Resume read_checkpoint_file(const std::filesystem::path& path);

}  // namespace granulab::cli
