// Sphere-pair candidates between different grains, with their tangential history.
//
// Two levels, because every grain is a rigid copy of one template: a broad phase on grain centres
// (cell grid, O(grains)) gives the grain pairs whose bounding spheres come within the skin plus a
// margin; a narrow phase maps grain b's spheres into grain a's body frame and looks them up in the
// template's cell grid. Spheres of one grain are never paired.
//
// Candidates are kept per grain pair, and each grain pair is searched again only when its own relative
// pose has drifted: its sphere pairs were every pair closer than d + skin, and no sphere of b has moved
// by a skin relative to a's body frame while |t_ab - t_ref| + r_max |R_ab - R_ref| < skin. Under the
// platens' compression neighbours move little relative to each other while the whole sample moves a
// lot, so this searches far fewer pairs than a global "a sphere moved half the skin" rule (which was
// one full search every ~50 steps on the reference crystal). The broad phase is redone when a grain
// has moved half the margin; the wall candidates when a sphere and its wall have moved a skin together.
//
// Layout: grain pairs sorted by (a, b) with a < b, including those with no sphere pair (they are
// watched for drift); each owns a contiguous block of sphere-pair keys (i << 16 | j, i in a, j in b)
// sorted ascending, and a parallel array of shear-history vectors. A pair searched again merges its old
// and new sorted blocks, so a sphere pair that stays a candidate keeps its history.
// Buffers are reused across updates: no allocation once they have grown to size.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/boundary/wall.h"
#include "engine/core/checkpoint.h"
#include "engine/contact/template_grid.h"
#include "engine/dynamics/bodies.h"

namespace granulab {

/// The candidate sphere pairs of two bodies: a contiguous block of the sorted key array.
struct BodyPairSpan {
  BodyId a, b;          ///< a < b
  std::uint32_t first;  ///< index of the first sphere pair of this grain pair
  std::uint32_t count;  ///< number of sphere pairs (0: watched, none within d + skin)
};

inline std::uint32_t sphere_pair_key(LocalSphereId i, LocalSphereId j) { return std::uint32_t(i) << 16 | j; }
inline LocalSphereId key_first(std::uint32_t key) { return LocalSphereId(key >> 16); }
inline LocalSphereId key_second(std::uint32_t key) { return LocalSphereId(key & 0xffff); }

/// Sphere-wall candidates, key = wall << 32 | global sphere index, sorted.
inline std::uint64_t wall_pair_key(std::uint32_t wall, std::uint32_t sphere) {
  return std::uint64_t(wall) << 32 | sphere;
}

/// The shear displacement of every sphere-pair candidate (m), one array per component: the contact loop
/// then loads and stores each component of consecutive pairs as one vector, where an array of Vec3
/// (every third double) cost eight scalar loads and a scatter per component. A law whose contacts outlive
/// delta = 0 (jkr) also keeps each candidate's bond flag (1 bonded, 0 not); other laws leave `bond` empty.
struct ShearHistory {
  std::vector<double> x, y, z, bond;
  bool bonds = false;  ///< whether `bond` is kept

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) {
    x.resize(n), y.resize(n), z.resize(n);
    if (bonds) bond.resize(n);
  }
  Vec3 get(std::size_t k) const { return {x[k], y[k], z[k]}; }
  void set(std::size_t k, const Vec3& v) { x[k] = v.x(), y[k] = v.y(), z[k] = v.z(); }
  /// Candidate k takes candidate o's history (and bond) from `from`.
  void take(std::size_t k, const ShearHistory& from, std::size_t o) {
    x[k] = from.x[o], y[k] = from.y[o], z[k] = from.z[o];
    if (bonds) bond[k] = from.bond[o];
  }
  void clear(std::size_t k) {
    x[k] = y[k] = z[k] = 0;
    if (bonds) bond[k] = 0;
  }
};

/// What the last update() did.
struct NeighborUpdate {
  bool broad = false;                ///< the grain pairs were found again
  std::uint32_t pairs_searched = 0;  ///< grain pairs whose sphere pairs were searched
  bool walls = false;                ///< the wall candidates were found again
  bool any() const { return broad || pairs_searched > 0 || walls; }
};

class NeighborList {
 public:
  /// `offsets`: template body-frame sphere centres; `diameter` of every sphere; `skin` (m); `min_scale`:
  /// the smallest Bodies::scale to expect (grains are never larger than the template).
  NeighborList(const std::vector<Vec3>& offsets, double diameter, double skin, double min_scale = 1);
  /// Keep a bond flag per candidate (a law whose contacts outlive delta = 0); call before the first update().
  void keep_bonds() { history_.bonds = old_history_.bonds = true; }

  /// Brings the candidates up to date with the bodies' poses and the walls (call before every force
  /// evaluation); cheap when nothing has drifted.
  NeighborUpdate update(const Bodies& bodies, const std::vector<Wall>& walls);
  /// Forgets every list (bodies or walls were added): the next update() starts from scratch.
  void invalidate() { built_ = false; }

  double skin() const { return skin_; }
  double cutoff() const { return cutoff_; }
  /// Grain centres closer than this at the last broad phase are watched (m).
  double broad_cutoff() const { return grain_cutoff_ + margin_; }
  const std::vector<BodyPairSpan>& body_pairs() const { return pairs_; }
  /// Whether the last update() searched grain pair p again (its candidates may have changed); every pair after a
  /// broad phase.
  bool searched(std::size_t p) const { return p < search_.size() && search_[p] != 0; }
  const std::vector<std::uint32_t>& keys() const { return keys_; }
  ShearHistory& history() { return history_; }
  const ShearHistory& history() const { return history_; }
  const std::vector<std::uint64_t>& wall_keys() const { return wall_keys_; }
  std::vector<Vec3>& wall_history() { return wall_history_; }

  /// The candidates, their shear history and the poses they were found at, exactly (checkpoints);
  /// the old_* lists are scratch.
  void state(CheckpointWriter& w) const { fields(w, *this); }
  void state(CheckpointReader& r) { fields(r, *this); }

 private:
  template <class Archive, class Self>
  static void fields(Archive& a, Self& list) {
    a.section("neighbors");
    a.value(list.built_);
    a.values(list.pairs_);
    a.values(list.frame_t_);
    a.values(list.frame_q_);
    a.values(list.keys_);
    a.values(list.history_.x);
    a.values(list.history_.y);
    a.values(list.history_.z);
    a.values(list.history_.bond);
    a.values(list.broad_position_);
    a.values(list.wall_keys_);
    a.values(list.wall_history_);
    a.values(list.wall_body_position_);
    a.values(list.wall_body_orientation_);
    a.values(list.wall_point_);
  }
  bool broad_phase_due(const Bodies& bodies) const;
  bool wall_phase_due(const Bodies& bodies, const std::vector<Wall>& walls) const;
  /// Marks (search_) the grain pairs that drifted by at least `threshold` (m); returns how many.
  std::uint32_t mark_drifted(const Bodies& bodies, double threshold);
  void retire_candidates();
  void broad_phase(const Bodies& bodies);
  void search_and_merge(const Bodies& bodies);
  void wall_phase(const Bodies& bodies, const std::vector<Wall>& walls);

  std::vector<Vec3> offsets_;
  std::vector<double> offset_x_, offset_y_, offset_z_;  // the same, one array per component (vector loops)
  double radius_, skin_, cutoff_, reach_, grain_cutoff_, margin_;
  TemplateGrid grid_;
  bool built_ = false;

  std::vector<BodyPairSpan> pairs_, old_pairs_;
  // Per grain pair, b's pose in a's body frame when last searched: x_b - x_a in a's frame (m), q_a^-1 q_b.
  std::vector<Vec3> frame_t_;
  std::vector<Quat> frame_q_;
  std::vector<std::uint32_t> keys_, old_keys_;
  ShearHistory history_, old_history_;
  std::vector<Vec3> broad_position_;  // grain centres at the last broad phase
  std::vector<std::uint64_t> wall_keys_, old_wall_keys_;
  std::vector<Vec3> wall_history_, old_wall_history_;
  std::vector<Vec3> wall_body_position_, wall_point_;  // poses and wall points at the last wall phase
  std::vector<Quat> wall_body_orientation_;

  // Scratch reused across updates.
  std::vector<std::pair<std::uint64_t, BodyId>> cell_keys_;
  std::vector<std::vector<std::uint32_t>> thread_keys_;
  std::vector<std::uint8_t> search_;  // per grain pair: search its sphere pairs in this update
  std::vector<std::uint32_t> pair_thread_, pair_offset_, old_index_;
};

}  // namespace granulab
