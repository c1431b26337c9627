// Loading programs (Fig. 1c of the paper: compression cycles at increasing strain): after confinement,
// a list of segments run in order, each moving the top platen at the speed of the rate number in force
// (compress or release to a strain, release until the deviator falls to a value) or holding it still.
// Without a program the run is one compression to max_strain.
#pragma once

#include <cstdint>
#include <vector>

namespace granulab {

struct LoadSegment {
  enum class Kind : std::uint32_t { to_strain, to_deviator, hold };
  Kind kind = Kind::to_strain;
  double value = 0;         ///< to_strain: axial strain (-); to_deviator: deviator (Pa); hold: unused
  std::uint64_t steps = 0;  ///< hold: time steps (-)
};

/// What a segment did, as run: the rows it spans and how the platen moved.
struct SegmentRecord {
  LoadSegment::Kind kind = LoadSegment::Kind::to_strain;
  int direction = 0;            ///< +1 compressing, -1 releasing, 0 held still
  std::uint64_t first_row = 0;  ///< the row it started from (the previous segment's last row)
  std::uint64_t last_row = 0;   ///< its last row (recorded when it ended)
  std::uint64_t steps = 0;      ///< time steps it took (-)
};

const char* segment_kind_name(LoadSegment::Kind kind);

/// The axial strain the platen travels, either way, over a program started at strain 0 (-). Where a
/// to_deviator segment ends is not known in advance: it counts as releasing half the strain reached.
double planned_travel(const std::vector<LoadSegment>& program);
/// The travel of each segment (-), a to_deviator segment counted as giving back `release_fraction` of the
/// strain reached.
std::vector<double> planned_segment_travels(const std::vector<LoadSegment>& program, double release_fraction);
/// An upper bound of that travel (-): a to_deviator segment may release down to a strain of -0.05 (then
/// the run fails). For cost estimates, which budgets and time limits rely on.
double travel_bound(const std::vector<LoadSegment>& program);
/// The time steps of the program's hold segments (-).
double hold_steps(const std::vector<LoadSegment>& program);

/// Whether a moving segment slows down before it ends: a to_strain followed by another, and a release to a
/// deviator even as the last segment (where it ends is a cycle's residual strain). The one rule the run and
/// the cost model share.
bool slows_down_at_end(const LoadSegment& segment, bool last);

/// The platen's speed as a fraction of the program's speed, `t` (s) into a segment that moves it:
/// it accelerates linearly over `ramp` (s) from rest, since a sudden start sends a stress wave of
/// amplitude E R through the sample; a segment that slows_down_at_end() also slows down over its last
/// `ramp` of travel, `remaining` (s at full speed), to 5 % of the speed at which it stops, so that
/// turning points are not struck either.
double platen_speed_fraction(double t, double ramp, double remaining, bool slow_down);

}  // namespace granulab
