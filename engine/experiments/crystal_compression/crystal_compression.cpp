#include "engine/experiments/crystal_compression/crystal_compression.h"

#include "engine/analysis/curve_peak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "engine/crystal/end_layers.h"
#include "engine/framework/energy_report.h"


namespace granulab {

const std::vector<CurveColumn>& CrystalRow::columns() {
  static const std::vector<CurveColumn> c = [] {
    std::vector<CurveColumn> c = {
      {"strain", "-", "axial strain: platen approach / initial length"},
      {"stress_top", "Pa", "top platen force / initial cross-section, compressive positive"},
      {"stress_bottom", "Pa", "bottom platen force / initial cross-section, compressive positive"},
      {"deviator", "Pa", "mean of the two platen stresses - p0"},
      {"lateral_strain_x", "-", "change of width / width, extension positive"},
      {"lateral_strain_y", "-", "change of thickness / thickness, extension positive"},
      {"lateral_stress", "Pa", "mean lateral stress the packing carries (virial)"},
      {"kinetic_elastic_ratio", "-", "kinetic / elastic energy", 6},
      {"contacts", "-", "sphere pairs in contact", 0},
      {"sliding_contacts", "-", "of which at the Coulomb limit", 0},
      {"segment", "-", "loading.program segment the row belongs to (0 without a program)", 0},
    };
    c.insert(c.end(), energy_columns().begin(), energy_columns().end());
    return c;
  }();
  return c;
}

std::vector<double> CrystalRow::values() const {
  std::vector<double> v = {strain,           stress_top,       stress_bottom,          deviator,
                           lateral_strain_x, lateral_strain_y, lateral_stress,         kinetic_elastic_ratio,
                           double(contacts), double(sliding_contacts), double(segment)};
  append_energy_values(energy, v);
  return v;
}

std::pair<double, double> first_yield_peak(const std::vector<CrystalRow>& curve, double p0, double drop) {
  std::vector<double> deviator;
  for (const CrystalRow& row : curve) deviator.push_back(row.deviator);
  const CurvePeak p = first_peak(deviator, 0.1 * p0, drop);
  return {curve.empty() ? 0.0 : curve[p.row].strain, p.value};
}


double default_compression_rate_number(double confining_pressure, double youngs_modulus) {
  // 1.5 x p0 / E, in this order: 60 kPa and 3 GPa give the double nearest 3e-5 (1.5 x 2e-5 rounds above it).
  return std::clamp(1.5 * confining_pressure / youngs_modulus, 1e-8, 0.1);
}

namespace {
CrystalParams with_rate(CrystalParams p) {
  if (!(p.rate_number > 0))
    p.rate_number = default_compression_rate_number(p.confining_pressure, p.material.youngs_modulus);
  return p;
}
}  // namespace

CrystalCompression::CrystalCompression(const CrystalParams& params) : params_(with_rate(params)), sample_(params_) {}

CrystalRow CrystalCompression::measure(double strain) const {
  CrystalRow row;
  const World& world = sample_.world();
  const auto& x = world.bodies().position;
  row.strain = strain;
  row.stress_top = sample_.axial_stress(sample_.top_wall());
  row.stress_bottom = sample_.axial_stress(sample_.bottom_wall());
  row.deviator = (row.stress_top + row.stress_bottom) / 2 - params_.confining_pressure;
  const double width = mean_coordinate(sample_.side(1), x, 0) - mean_coordinate(sample_.side(0), x, 0);
  const double thickness = mean_coordinate(sample_.side(3), x, 1) - mean_coordinate(sample_.side(2), x, 1);
  row.lateral_strain_x = ref_width_ > 0 ? width / ref_width_ - 1 : 0;
  row.lateral_strain_y = ref_thickness_ > 0 ? thickness / ref_thickness_ - 1 : 0;
  const auto [sx, sy] = sample_.lateral_stresses();
  row.lateral_stress = (sx + sy) / 2;
  row.kinetic_elastic_ratio = sample_.kinetic_elastic_ratio();
  row.contacts = world.contact_stats().contacts;
  row.sliding_contacts = world.contact_stats().sliding;
  row.energy = world.energy_balance();
  return row;
}

double CrystalCompression::deviator() const {
  return (sample_.axial_stress(sample_.top_wall()) + sample_.axial_stress(sample_.bottom_wall())) / 2 -
         params_.confining_pressure;
}

GrainSnapshot CrystalCompression::snapshot(double strain) const { return crystal_snapshot(sample_, ref_, strain); }

void CrystalCompression::take_reference() {
  ref_.take(sample_);
  sample_.world().start_energy_balance();
  const std::vector<Vec3>& x = ref_.position;
  ref_width_ = mean_coordinate(sample_.side(1), x, 0) - mean_coordinate(sample_.side(0), x, 0);
  ref_thickness_ = mean_coordinate(sample_.side(3), x, 1) - mean_coordinate(sample_.side(2), x, 1);
  const auto& walls = sample_.world().walls();
  ref_length_ = walls[sample_.top_wall()].point.z() - walls[sample_.bottom_wall()].point.z();
}

template <class Archive, class Self, class At, class Result>
void CrystalCompression::state(Archive& a, Self& self, At& at, Result& r) {
  a.section("crystal_compression");
  a.value(at);
  a.value(r.confinement);
  a.values(r.curve);
  a.values(r.segments);
  a.values(r.stress_drops);
  snapshot_marks(a, r.snapshots);
  a.values(self.ref_.position);
  a.values(self.ref_.orientation);
  a.values(self.ref_.interfaces);
  a.value(self.ref_length_), a.value(self.ref_width_), a.value(self.ref_thickness_);
}

void CrystalCompression::save(CheckpointWriter& out, const Position& at, const CrystalResult& r) const {
  sample_.save(out);
  state(out, *this, at, r);
}

void CrystalCompression::restore(const CheckpointSource& checkpoint, Position& at, CrystalResult& r) {
  CheckpointReader in(checkpoint);
  sample_.restore(in);
  state(in, *this, at, r);
  in.finish();
}

namespace {

std::string percent(double strain) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g %%", 100 * strain);
  return text;
}

}  // namespace

bool bag_wraps(const CrystalParams& p) {
  return p.confinement == Confinement::membrane && p.knockout_ids.empty() && p.knockout_regions.empty();
}

bool bag_packs_first(const CrystalParams& p) { return bag_wraps(p) && p.imperfections.any(); }

// How much of the strain reached a release to a deviator of 0 gives back (-): mostly the bag pushing the bulged
// crystal back, so more the thicker the crystal. Measured (bench/README.md, "Cost estimates"; N_e = 4 and 10,
// 30 kPa, released from 0.5 and 1 %): 3 {111} layers gave back 6-24 %, 6 layers 29-44 %.
static double release_fraction(const CrystalParams& p) { return 0.45 * std::clamp((p.layers_y - 2) / 4.0, 0.0, 1.0); }

// Each moving segment: its travel at R c, plus what its ramps cost (drive_platen, platen_speed_fraction).
// The platen accelerates linearly over a ramp of ten wave transits (half a ramp lost); a to_strain segment
// followed by another slows down over its last ramp of travel, its speed in proportion to what is left (an
// exponential approach, 3 ramps to 5 % of full speed) then at 5 % for the rest (one more ramp): 3 ramps
// lost. A release to a deviator slows down the same way (its distance left extrapolated from the deviator
// left), even as the last segment, and gives back release_fraction() of the strain reached.

double expected_compression_confinement_steps(const CrystalParams& p) {
  if (p.confinement == Confinement::face_forces) return 0;
  if (bag_wraps(p) && !bag_packs_first(p))
    return double(p.equilibrium_checks) * p.membrane_interval;
  return expected_confinement_steps(p);
}

std::vector<WorkPhase> loading_phases(const CrystalParams& p, double length, double time_step) {
  const double c = crystal_wave_speed(p), speed = p.rate_number * c, ramp = 10 * length / c;
  std::vector<LoadSegment> program = p.program;
  if (program.empty()) program.push_back({LoadSegment::Kind::to_strain, p.max_strain, 0});
  const std::vector<double> travel = planned_segment_travels(program, release_fraction(p));
  std::vector<WorkPhase> out;
  for (std::size_t k = 0; k < program.size(); ++k) {
    const LoadSegment& s = program[k];
    if (s.kind == LoadSegment::Kind::hold) {
      out.push_back({"hold " + std::to_string(s.steps) + " steps", double(s.steps)});
      continue;
    }
    const bool slows_down = slows_down_at_end(s, k + 1 == program.size());
    const double seconds = travel[k] * length / speed + ramp * (0.5 + (slows_down ? 3.0 : 0.0));
    out.push_back({s.kind == LoadSegment::Kind::to_strain ? "to_strain " + percent(s.value)
                                                          : "to_deviator " + std::to_string(int(s.value)) + " Pa",
                   seconds / time_step});
  }
  return out;
}

double loading_steps_bound(const CrystalParams& p, double length) {
  const double c = crystal_wave_speed(p);
  const double travel = p.program.empty() ? p.max_strain : travel_bound(p.program);
  const double moves = p.program.empty() ? 1 : double(p.program.size());
  // The platen's travel at R c, and at most 4 ramps of ten wave transits per segment (loading_phases).
  return (travel * length / (p.rate_number * c) + moves * 40 * length / c) / crystal_time_step(p) +
         hold_steps(p.program);
}

}  // namespace granulab
