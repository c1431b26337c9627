#include "engine/crystal/loading_program.h"

#include <algorithm>
#include <cmath>

namespace granulab {

const char* segment_kind_name(LoadSegment::Kind kind) {
  switch (kind) {
    case LoadSegment::Kind::to_strain: return "to_strain";
    case LoadSegment::Kind::to_deviator: return "to_deviator";
    case LoadSegment::Kind::hold: return "hold_steps";
  }
  return "?";
}

namespace {

// The travel of each segment of a program whose to_deviator segments each leave the strain at release(strain).
template <class Release>
std::vector<double> travels(const std::vector<LoadSegment>& program, Release release) {
  std::vector<double> out;
  double strain = 0;
  for (const LoadSegment& s : program) {
    double to = strain;
    if (s.kind == LoadSegment::Kind::to_strain) to = s.value;
    if (s.kind == LoadSegment::Kind::to_deviator) to = release(strain);
    out.push_back(std::abs(to - strain)), strain = to;
  }
  return out;
}

double sum(const std::vector<double>& x) {
  double total = 0;
  for (double v : x) total += v;
  return total;
}

}  // namespace

// A release counted as giving back `release_fraction` of the strain reached (planned_travel, which spaces the
// curve rows of a program, keeps half: the reference crystal at 30 kPa, unloaded to a deviator of 0 at 0.5 to
// 2 %, gave back 37 to 47 % of it; README, "Loading cycles").
std::vector<double> planned_segment_travels(const std::vector<LoadSegment>& program, double release_fraction) {
  return travels(program, [release_fraction](double strain) { return strain * (1 - release_fraction); });
}

double planned_travel(const std::vector<LoadSegment>& program) { return sum(planned_segment_travels(program, 0.5)); }

double travel_bound(const std::vector<LoadSegment>& program) {
  return sum(travels(program, [](double) { return -0.05; }));
}

double hold_steps(const std::vector<LoadSegment>& program) {
  double steps = 0;
  for (const LoadSegment& s : program)
    if (s.kind == LoadSegment::Kind::hold) steps += double(s.steps);
  return steps;
}

bool slows_down_at_end(const LoadSegment& segment, bool last) {
  return segment.kind == LoadSegment::Kind::to_deviator || (segment.kind == LoadSegment::Kind::to_strain && !last);
}

double platen_speed_fraction(double t, double ramp, double remaining, bool slow_down) {
  double f = ramp > 0 ? std::min(1.0, t / ramp) : 1.0;
  if (slow_down && ramp > 0) f = std::min(f, std::max(0.05, remaining / ramp));
  return f;
}

}  // namespace granulab
