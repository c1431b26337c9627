// Grain pairs that are apart, and stay so without evaluating their candidates.
//
// A grain pair whose candidates all missed at its last evaluation, by at least a gap g (the nearest sphere centres
// d + g apart), cannot touch while b's spheres have moved by less than g relative to a's body frame: its candidates
// give no force, and their histories stay zero. That motion is bounded as the neighbour list bounds a pair's drift,
// |t - t0| + r_max |R - R0| (t = x_b - x_a in a's frame, R = R_a^T R_b, |R - R0| = 2 sin(theta / 2) for the angle
// theta of q0^-1 q; the triangle inequality on t + R o). Until then the contact stage skips the pair: the reference
// crystal skips 11 % of its candidates over a run to 10 % strain (20 % to 1 %), each a few nanoseconds of distance
// tests per step. A skipped pair's sums are the zeros its evaluation would give, so no result changes. Saved with
// the world, so that a resumed run skips what the uninterrupted one does (and counts it).
//
// A jkr bond holds beyond contact: such laws never skip.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/checkpoint.h"
#include "engine/core/types.h"
#include "engine/dynamics/bodies.h"

namespace granulab {

class OpenPairs {
 public:
  /// `reach`: the largest distance of a sphere centre from its grain's centre (m).
  explicit OpenPairs(double reach) : reach_(reach) {}

  /// n grain pairs, none known to be open (after the pairs were found again).
  void reset(std::size_t n);
  std::size_t size() const { return gap_.size(); }
  /// Pair p's candidates changed (it was searched again): evaluate it next time.
  void forget(std::size_t p) { gap_[p] = 0; }
  /// Whether pair p (bodies a, b) cannot touch yet: skip its evaluation.
  bool closed_off(std::size_t p, const Bodies& bodies, BodyId a, BodyId b) const;
  /// Pair p was evaluated: `nearest2`, the squared distance of its nearest sphere centres (m^2; 0 when unknown), and
  /// `diameter`, the distance at which they touch (m). Remembers the pair as open when nothing touches.
  void evaluated(std::size_t p, const Bodies& bodies, BodyId a, BodyId b, std::uint32_t contacts, double nearest2,
                 double diameter);

  /// Every pair's gap and pose, exactly (checkpoints).
  void state(CheckpointWriter& w) const { fields(w, *this); }
  void state(CheckpointReader& r) { fields(r, *this); }

 private:
  template <class Archive, class Self>
  static void fields(Archive& a, Self& pairs) {
    a.section("open_pairs");
    a.values(pairs.gap_);
    a.values(pairs.t0_);
    a.values(pairs.q0_);
  }

  double reach_;
  std::vector<double> gap_;  // per pair: how far its nearest spheres were apart at t0 (m), minus a margin; 0 unknown
  std::vector<Vec3> t0_;     // b's centre in a's frame at t0 (m)
  std::vector<Quat> q0_;     // q_a^-1 q_b at t0
};

}  // namespace granulab
