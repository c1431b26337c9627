// A uniform cell grid over the body-frame spheres of one grain template, built once per simulation.
// The narrow phase maps the spheres of grain b into grain a's body frame and looks them up here, so
// finding the sphere pairs of a grain pair costs O(spheres of b) instead of O(spheres of a x b).
#pragma once

#include <cstdint>
#include <vector>

#include "engine/core/types.h"

namespace granulab {

class TemplateGrid {
 public:
  TemplateGrid() = default;
  /// `cell` (m) must be >= the largest query radius.
  TemplateGrid(const std::vector<Vec3>& offsets, double cell);

  /// Calls visit(i) for every template sphere i within `radius` (<= cell) of body-frame point p.
  template <class Visit>
  void for_each_near(const Vec3& p, double radius, Visit&& visit) const {
    const Eigen::Vector3i c = cell_of(p);
    const double r2 = radius * radius;
    for (int x = std::max(c.x() - 1, 0); x <= std::min(c.x() + 1, dims_.x() - 1); ++x)
      for (int y = std::max(c.y() - 1, 0); y <= std::min(c.y() + 1, dims_.y() - 1); ++y)
        for (int z = std::max(c.z() - 1, 0); z <= std::min(c.z() + 1, dims_.z() - 1); ++z) {
          const int cell = (x * dims_.y() + y) * dims_.z() + z;
          for (std::uint32_t k = start_[cell]; k < start_[cell + 1]; ++k) {
            const std::uint16_t i = ids_[k];
            if ((points_[k] - p).squaredNorm() < r2) visit(i);
          }
        }
  }

 private:
  Eigen::Vector3i cell_of(const Vec3& p) const {
    const Vec3 f = (p - origin_) / cell_;
    return Eigen::Vector3i(int(std::floor(f.x())), int(std::floor(f.y())), int(std::floor(f.z())));
  }
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1;
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<std::uint32_t> start_;  // CSR: spheres of cell c are ids_[start_[c] .. start_[c+1])
  std::vector<std::uint16_t> ids_;
  std::vector<Vec3> points_;  // offsets in the same order as ids_, for locality
};

}  // namespace granulab
