// The vacuum bag: a confining pressure p0 on the lateral surface of the sample (docs/model.md, "Confinement").
// For each lateral face (+x, -x, +y, -y) a height map over the face plane, with cells finer than a
// sphere, records the outermost sphere surface in every cell; the grain owning it receives
// p0 x (cell area) along the inward face normal, applied at that surface point (so it also exerts a
// torque). Each surface grain is thus pushed in proportion to the area of its projection on the sample
// surface, and the set of surface grains follows the surface as it deforms when the map is rebuilt.
// Why the face normal and not the local slope of the height map: opposite faces then see the same
// projected footprint, so the bag exerts no net force on the sample, as a closed bag must not; a
// local slope measured on the faceted, jagged ends of the sample pushed the whole sample into one wall.
// Holes: a bag stretched over the surface does not reach into a hole (a knocked-out region); it spans
// it. A cell whose outermost sphere lies more than `bridge_depth` below the surface the bag lies on
// (enclosed pits and holes up to about twice `bridge_span` wide filled; see local_envelope) is bridged and receives no pressure, like an empty cell; otherwise the bag would push
// the grains seen through the hole and drive them through it, with nothing to stop them. The bag's load
// over a hole is dropped, not passed on to the hole's rim: where the two opposite faces bridge different
// areas, the bag exerts a net force of p0 times the difference (reported per face in the stats' areas).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/core/checkpoint.h"
#include "engine/core/types.h"

namespace granulab {

struct MembraneStats {
  double area[4] = {0, 0, 0, 0};  ///< projected area covered on +x, -x, +y, -y (m^2)
  /// Per face: mean coordinate along the face axis of the centres of the grains it pushes, weighted by
  /// the area each receives (m). The lever arm of the bag's load on the packing.
  double load_centre[4] = {0, 0, 0, 0};
  std::size_t grains = 0;   ///< grains receiving a membrane force
  double bridged_area = 0;  ///< area of bridged cells, all faces (m^2)
  double max_depth = 0;     ///< deepest pressed cell below the closed surface (m)
};

class Membrane {
 public:
  /// `pressure` p0 (Pa); `cell` height-map resolution (m); `bridge_span`, `bridge_depth` (m): see above
  /// (a span of 0 bridges nothing).
  Membrane(double pressure, double cell, double bridge_span = 0, double bridge_depth = 0);

  /// Recomputes the per-body forces and torques (overwriting `force`, `torque`) from the sphere
  /// centres (body-major, `per_body` spheres of radius `radius` each, times the body's `scale` if given:
  /// imperfect grains) and body centres.
  void apply(const std::vector<Vec3>& body_positions, const std::vector<Vec3>& spheres, std::size_t per_body,
             double radius, std::vector<Vec3>& force, std::vector<Vec3>& torque,
             const std::vector<double>* scale = nullptr);

  /// The same load on the two end faces (+z, -z), as if the bag were wrapped over them too: p0 x each
  /// grain's projected area along the inward face normal, added into `force` (applied at the grain's
  /// centre: no torque). Returns the faces' projected areas {+z, -z} (m^2). For fixed confining forces.
  std::pair<double, double> end_forces(const std::vector<Vec3>& body_positions, const std::vector<Vec3>& spheres,
                                       std::size_t per_body, double radius, std::vector<Vec3>& force,
                                       const std::vector<double>* scale = nullptr) const;

  double pressure() const { return pressure_; }
  void set_pressure(double p) { pressure_ = p; }
  const MembraneStats& stats() const { return stats_; }
  /// Pressure and last stats (checkpoints); the height maps are rebuilt at every apply().
  void save(CheckpointWriter& w) const;
  void restore(CheckpointReader& r);

 private:
  // Per axis (x, y): the height maps of its two faces and what they push, reused between calls.
  struct AxisScratch {
    std::vector<double> height[2];
    std::vector<std::uint32_t> owner[2];
    std::vector<Vec3> force, torque;
    std::vector<bool> touched;
    std::vector<double> envelope, padded, pass;  // the bag's surface; the padded closing and a pass of it
    std::vector<bool> flooded;
    std::vector<std::pair<double, std::size_t>> heap;  // the flood's queue storage, reused
    double area[2] = {0, 0}, load_centre[2] = {0, 0}, bridged_area = 0, max_depth = 0;
  };
  /// The maps' common origin `lo` (on the cell lattice) and far corner `hi`; throws when the sample has flown apart.
  void bounds(const std::vector<Vec3>& spheres, double radius, Vec3& lo, Vec3& hi) const;
  void local_envelope(const std::vector<double>& height, int nu, int nv, AxisScratch& a) const;
  void map_axis(int axis, const Vec3& lo, const Vec3& hi, const std::vector<Vec3>& body_positions,
                const std::vector<Vec3>& spheres, std::size_t per_body, double radius, const std::vector<double>* scale,
                AxisScratch& a) const;

  double pressure_, cell_, bridge_span_, bridge_depth_;
  MembraneStats stats_;
  AxisScratch scratch_[2];
};

}  // namespace granulab
