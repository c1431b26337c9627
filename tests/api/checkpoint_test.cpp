// Checkpoints: a run interrupted at any safe point and resumed from its last checkpoint gives, byte
// for byte, the curve and snapshots of an uninterrupted run, for every registered experiment; a
// checkpoint of another spec, or a damaged one, is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <optional>
#include <string>

#include "api/runner.h"
#include "api/spec.h"
#include "engine/core/checkpoint.h"
#include "engine/experiments/registry.h"

namespace granulab::api {
namespace {

// Short runs with several safe points in every phase (two_cube: every 64 steps; the crystal: every
// confinement check and every 100 compression steps).
const std::map<std::string, std::string> kSpecs = {
    {"two_cube_sliding", R"({"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3},
      "loading": {"rate_number": 1e-3}, "output": {"curve_points": 7}})"},
    {"crystal_compression", R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
      "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2}, "loading": {"confining_pressure": 30e3,
      "max_strain": 2e-3, "rate_number": 2e-5}, "output": {"curve_points": 12, "snapshot_strains": [0, 1e-3, 2e-3]}})"},
    {"crystal_confinement", R"({"experiment": "crystal_confinement", "grain": {"edge_spheres": 3},
      "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2}, "loading": {"confining_pressure": 30e3}})"},
    // A shear there and back, with a hold between: the layers, the dead load's velocity and the segment under way.
    {"crystal_shear", R"({"experiment": "crystal_shear", "grain": {"edge_spheres": 3},
      "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 4, "layers_y": 2}, "loading": {"confining_pressure": 30e3,
      "max_shear_strain": 2e-3, "rate_number": 1e-4, "program": [{"to_shear_strain": 1e-3}, {"hold_steps": 200},
      {"to_shear_strain": -5e-4}]}, "output": {"curve_points": 12, "snapshot_strains": [0, 1e-3]}})"},
    // Through every set: conditioning, affine ramps, relaxed ramps and holds (the interior's motions, the hold's checks).
    {"crystal_stiffness", R"({"experiment": "crystal_stiffness", "grain": {"edge_spheres": 3},
      "crystal": {"lattice": "sc", "grains_x": 3, "rows_z": 3, "layers_y": 3}, "loading": {"confining_pressure": 30e3,
      "ramp_transits": 1, "relax_checks": 1}})"},
    // A cohesive crystal out of its bag, pulled past its peak (the peak tracked every step, the grips, the layers).
    {"crystal_tension", R"({"experiment": "crystal_tension", "grain": {"edge_spheres": 3},
      "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 3, "layers_y": 2}, "contact": {"normal": "dmt",
      "surface_energy": 1}, "loading": {"confining_pressure": 100, "confinement": "none", "max_strain": 3e-4},
      "output": {"curve_points": 12, "snapshot_strains": [0, 1e-4]}})"},
};

struct Died {};

// Checkpoints at every safe point; after checkpoint number `die_after` (1-based; 0 = never) it lets
// `linger` more safe points pass, making rows the checkpoint does not cover, then "dies".
class DyingSink : public MemorySink {
 public:
  DyingSink(int die_after, int linger) : die_after_(die_after), linger_(linger) {}
  bool checkpoint_due() override {
    if (taken_ >= die_after_ && die_after_ > 0 && linger_-- <= 0) throw Died();
    return true;
  }
  void checkpoint(const CheckpointContent& content, std::size_t rows, std::size_t snapshots) override {
    state = checkpoint_bytes(content);
    last = Resume{checkpoint_source(state), rows, snapshots};
    ++taken_;
  }
  std::string state;  ///< the last checkpoint's bytes
  std::optional<Resume> last;
  int taken_ = 0;

 private:
  int die_after_, linger_;
};

std::string snapshots_text(const MemorySink& s) {
  std::string out;
  for (const auto& [strain, json] : s.snapshots_) out += std::to_string(strain) + json.dump() + "\n";
  return out;
}

// Interrupts a run of `text` at several checkpoints and resumes it: the same curve, snapshots and results.
void expect_resumes_bit_identical(const std::string& text) {
  const Spec spec = parse_spec_text(text);
  DyingSink whole(0, 0);
  run(spec, whole);
  const int safe_points = whole.taken_;
  ASSERT_GE(safe_points, 4);
  if (whole.summary_.contains("compression_steps")) {  // the last interruption falls in the compression
    ASSERT_GE(whole.summary_.at("compression_steps").get<double>(), 300);
  }
  // Die after the first, a middle and the last checkpoint, each time a few safe points later; resume
  // (twice in a row for the middle one: a resumed run is itself interrupted and resumed).
  for (const int die_after : {1, safe_points / 2, std::max(2, safe_points - 150), safe_points - 2}) {
    SCOPED_TRACE("died after checkpoint " + std::to_string(die_after) + " of " + std::to_string(safe_points));
    DyingSink first(die_after, 1);
    EXPECT_THROW(run(spec, first), Died);
    ASSERT_TRUE(first.last);
    Resume from = *first.last;
    DyingSink resumed(die_after == safe_points / 2 ? 1 : 0, 1);
    resumed.curve_csv_ = first.curve_csv_;  // what the interrupted run left, rows past the checkpoint included
    resumed.snapshots_ = first.snapshots_;
    if (die_after == safe_points / 2) {
      EXPECT_THROW(run(spec, resumed, &from), Died);
      from = *resumed.last;
      DyingSink again(0, 0);
      again.curve_csv_ = resumed.curve_csv_;
      again.snapshots_ = resumed.snapshots_;
      run(spec, again, &from);
      EXPECT_EQ(again.curve_csv_, whole.curve_csv_);
      EXPECT_EQ(snapshots_text(again), snapshots_text(whole));
      EXPECT_EQ(again.summary_.at("steps"), whole.summary_.at("steps"));
      continue;
    }
    run(spec, resumed, &from);
    EXPECT_EQ(resumed.curve_csv_, whole.curve_csv_);
    EXPECT_EQ(snapshots_text(resumed), snapshots_text(whole));
    EXPECT_EQ(resumed.summary_.at("steps"), whole.summary_.at("steps"));
    for (const char* key : {"first_yield", "segments", "cycles", "fixed_forces", "peak", "snapshots",
                            "tensile_strength", "failure_strain", "failure_plane", "stopped", "mean_candidates",
                            "mean_skipped_candidates"}) {
      if (whole.summary_.contains(key)) {
        EXPECT_EQ(resumed.summary_.at(key), whole.summary_.at(key)) << key;
      }
    }
  }
}

TEST(Checkpoints, ResumedRunsAreBitIdenticalToUninterruptedOnes) {
  for (const ExperimentType& t : experiment_types()) {
    SCOPED_TRACE(t.name);
    ASSERT_TRUE(kSpecs.count(t.name)) << "add a short spec for the new experiment here";
    expect_resumes_bit_identical(kSpecs.at(t.name));
  }
}

// A loading program (release to a deviator, a hold, a reload), fixed confining forces and imperfect grains:
// the segment under way, the fixed forces and the grains' sizes all come back from a checkpoint.
TEST(Checkpoints, AProgramWithFixedForcesAndImperfectGrainsResumesBitIdentical) {
  expect_resumes_bit_identical(R"({"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
      "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
      "imperfections": {"size_dispersion": 0.002, "misorientation": 0.5, "seed": 3},
      "loading": {"confining_pressure": 30e3, "max_strain": 2e-3, "rate_number": 2e-5, "confinement": "fixed_forces",
        "program": [{"to_strain": 1.5e-3}, {"to_deviator": 0}, {"hold_steps": 200}, {"to_strain": 2e-3}]},
      "output": {"curve_points": 12, "snapshot_strains": [0, 1e-3, 2e-3]}})");
}

TEST(Checkpoints, AnotherSpecsOrADamagedCheckpointIsRefused) {
  const Spec spec = parse_spec_text(kSpecs.at("crystal_compression"));
  DyingSink first(1, 0);
  EXPECT_THROW(run(spec, first), Died);
  ASSERT_TRUE(first.last);

  nlohmann::json bigger = nlohmann::json::parse(kSpecs.at("crystal_compression"));
  bigger["crystal"]["grains_x"] = 3;
  MemorySink other;
  EXPECT_THROW(run(parse_spec(bigger), other, &*first.last), CheckpointError);

  std::string bytes = first.state;
  bytes[bytes.size() / 2] ^= 0x01;
  Resume damaged{checkpoint_source(bytes), first.last->rows, first.last->snapshots};
  MemorySink sink;
  EXPECT_THROW(run(spec, sink, &damaged), CheckpointError);
  Resume cut{checkpoint_source(first.state.substr(0, first.state.size() - 100)), first.last->rows, 0};
  EXPECT_THROW(run(spec, sink, &cut), CheckpointError);
  Resume nothing{checkpoint_source("short"), 0, 0};
  EXPECT_THROW(run(spec, sink, &nothing), CheckpointError);
}

// The writer's chunks: whatever their size, the bytes are those of the whole (the chunk size is the
// writer's only memory), no chunk exceeds it, and a reader over the chunks, fetched one at a time,
// restores the run as from the whole. A chunk missing reads as a truncated checkpoint.
TEST(Checkpoints, ChunksOfAnySizeMakeTheSameCheckpoint) {
  const Spec spec = parse_spec_text(kSpecs.at("crystal_compression"));
  struct ChunkingSink : MemorySink {
    bool checkpoint_due() override { return chunks.empty(); }
    void checkpoint(const CheckpointContent& content, std::size_t r, std::size_t s) override {
      whole = checkpoint_bytes(content);
      CheckpointWriter w([this](const char* data, std::size_t n) { chunks.emplace_back(data, n); }, 1000);
      content(w);
      w.finish();
      rows = r, snapshots = s;
    }
    std::string whole;
    std::vector<std::string> chunks;
    std::size_t rows = 0, snapshots = 0;
  } taken;
  DyingSink direct(0, 0);
  run(spec, direct);
  run(spec, taken);
  ASSERT_GT(taken.chunks.size(), 10u);
  std::string joined;
  for (const std::string& c : taken.chunks) {
    EXPECT_LE(c.size(), 1000u);
    joined += c;
  }
  EXPECT_EQ(joined, taken.whole);
  std::size_t fetched = 0;
  Resume from{chunked_checkpoint_source(joined.size(), std::int64_t(taken.chunks.size()),
                                        [&](std::int64_t k) {
                                          ++fetched;
                                          return taken.chunks.at(std::size_t(k));
                                        }),
              taken.rows, taken.snapshots};
  MemorySink resumed;
  resumed.curve_csv_ = taken.curve_csv_;
  resumed.snapshots_ = taken.snapshots_;
  run(spec, resumed, &from);
  EXPECT_EQ(resumed.curve_csv_, direct.curve_csv_);
  // The checksum's pass, then the restore's (which need not fetch a last chunk holding only the checksum).
  EXPECT_GE(fetched, 2 * taken.chunks.size() - 1);
  EXPECT_LE(fetched, 2 * taken.chunks.size());
  Resume holed{chunked_checkpoint_source(joined.size(), std::int64_t(taken.chunks.size()),
                                         [&](std::int64_t k) {
                                           return k == 3 ? std::string() : taken.chunks.at(std::size_t(k));
                                         }),
               taken.rows, taken.snapshots};
  MemorySink sink;
  EXPECT_THROW(run(spec, sink, &holed), CheckpointError);
}

}  // namespace
}  // namespace granulab::api
