// Sphere-pair candidates between different grains, with their tangential history.
//
// Two levels, because every grain is a rigid copy of one template: a broad phase on grain centres
// (cell grid, O(grains)) gives the grain pairs whose bounding spheres come within the skin; a narrow
// phase maps grain b's spheres into grain a's body frame and looks them up in the template's cell grid.
// Spheres of one grain are never paired. Candidates are kept while every sphere has moved less than
// half the skin since the build (World decides when to rebuild).
//
// Layout: grain pairs sorted by (a, b) with a < b; each owns a contiguous block of sphere-pair keys
// (i << 16 | j, i in a, j in b) sorted ascending, and a parallel array of shear-history vectors.
// A rebuild merges the old and new sorted lists so a pair that stays a candidate keeps its history.
// Buffers are reused across rebuilds: no allocation once they have grown to size.
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
  std::uint32_t count;  ///< number of sphere pairs
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
/// (every third double) cost eight scalar loads and a scatter per component.
struct ShearHistory {
  std::vector<double> x, y, z;

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n) { x.resize(n), y.resize(n), z.resize(n); }
  Vec3 get(std::size_t k) const { return {x[k], y[k], z[k]}; }
  void set(std::size_t k, const Vec3& v) { x[k] = v.x(), y[k] = v.y(), z[k] = v.z(); }
};

class NeighborList {
 public:
  /// `offsets`: template body-frame sphere centres; `diameter` of every sphere; `skin` (m).
  NeighborList(const std::vector<Vec3>& offsets, double diameter, double skin);

  /// Rebuilds candidates for the given poses and walls, carrying history across.
  /// `sphere_positions` are world positions, body-major (body * spheres_per_body + local).
  void rebuild(const Bodies& bodies, const std::vector<Vec3>& sphere_positions, const std::vector<Wall>& walls);

  double skin() const { return skin_; }
  double cutoff() const { return cutoff_; }
  const std::vector<BodyPairSpan>& body_pairs() const { return pairs_; }
  const std::vector<std::uint32_t>& keys() const { return keys_; }
  ShearHistory& history() { return history_; }
  const std::vector<std::uint64_t>& wall_keys() const { return wall_keys_; }
  std::vector<Vec3>& wall_history() { return wall_history_; }

  /// The candidates and their shear history exactly (checkpoints); the old_* lists are scratch.
  void state(CheckpointWriter& w) const { fields(w, *this); }
  void state(CheckpointReader& r) { fields(r, *this); }

 private:
  template <class Archive, class Self>
  static void fields(Archive& a, Self& list) {
    a.section("neighbors");
    a.values(list.pairs_);
    a.values(list.keys_);
    a.values(list.history_.x);
    a.values(list.history_.y);
    a.values(list.history_.z);
    a.values(list.wall_keys_);
    a.values(list.wall_history_);
  }
  void broad_phase(const Bodies& bodies);
  void narrow_phase(const Bodies& bodies);
  void wall_phase(const Bodies& bodies, const std::vector<Vec3>& sphere_positions, const std::vector<Wall>& walls);

  std::vector<Vec3> offsets_;
  double radius_, skin_, cutoff_, grain_cutoff_;
  TemplateGrid grid_;

  std::vector<BodyPairSpan> pairs_, old_pairs_;
  std::vector<std::uint32_t> keys_, old_keys_;
  ShearHistory history_, old_history_;
  std::vector<std::uint64_t> wall_keys_, old_wall_keys_;
  std::vector<Vec3> wall_history_, old_wall_history_;

  // Scratch reused across rebuilds.
  std::vector<std::pair<std::uint64_t, BodyId>> cell_keys_;
  std::vector<std::vector<std::uint32_t>> thread_keys_;
  std::vector<std::uint32_t> pair_thread_, pair_offset_;
};

}  // namespace granulab
