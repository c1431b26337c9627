#include "engine/contact/template_grid.h"

#include <cmath>
#include <stdexcept>

namespace granulab {

TemplateGrid::TemplateGrid(const std::vector<Vec3>& offsets, double cell) : cell_(cell) {
  if (!(cell > 0) || offsets.empty()) throw std::invalid_argument("template grid needs spheres and cell > 0");
  Vec3 lo = offsets.front(), hi = offsets.front();
  for (const Vec3& o : offsets) lo = lo.cwiseMin(o), hi = hi.cwiseMax(o);
  // One spare cell on each side, so a query point just outside the clump still sees its neighbours
  // and cell_of() never needs clamping for points that can have any.
  origin_ = lo - Vec3::Constant(cell);
  for (int k = 0; k < 3; ++k) dims_[k] = int(std::floor((hi[k] - origin_[k]) / cell)) + 2;
  const std::size_t n_cells = std::size_t(dims_.x()) * dims_.y() * dims_.z();
  std::vector<std::uint32_t> count(n_cells + 1, 0);
  std::vector<int> cell_index(offsets.size());
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    const Eigen::Vector3i c = cell_of(offsets[i]);
    cell_index[i] = (c.x() * dims_.y() + c.y()) * dims_.z() + c.z();
    ++count[cell_index[i] + 1];
  }
  start_.assign(n_cells + 1, 0);
  for (std::size_t c = 0; c < n_cells; ++c) start_[c + 1] = start_[c] + count[c + 1];
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  ids_.resize(offsets.size());
  points_.resize(offsets.size());
  for (std::size_t i = 0; i < offsets.size(); ++i) {
    const std::uint32_t k = fill[cell_index[i]]++;
    ids_[k] = std::uint16_t(i);
    points_[k] = offsets[i];
  }
}

}  // namespace granulab
