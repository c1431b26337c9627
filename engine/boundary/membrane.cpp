#include "engine/boundary/membrane.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <omp.h>
#include <stdexcept>
#include <string>
#include <utility>

namespace granulab {

namespace {
// Per map; a cell costs about 50 bytes of scratch and both maps are built at once, so 1 GB in all. The
// reference crystal's maps have about 11,000 cells, the largest crystal the spec admits about 3e6.
constexpr double kMaxCells = 1e7;
}  // namespace

Membrane::Membrane(double pressure, double cell, double bridge_span, double bridge_depth)
    : pressure_(pressure), cell_(cell), bridge_span_(bridge_span), bridge_depth_(bridge_depth) {}

void Membrane::apply(const std::vector<Vec3>& body_positions, const std::vector<Vec3>& spheres, std::size_t per_body,
                     double radius, std::vector<Vec3>& force, std::vector<Vec3>& torque,
                     const std::vector<double>* scale) {
  std::fill(force.begin(), force.end(), Vec3::Zero());
  std::fill(torque.begin(), torque.end(), Vec3::Zero());
  stats_ = MembraneStats{};
  if (spheres.empty()) return;
  Vec3 lo, hi;
  bounds(spheres, radius, lo, hi);

  // The two faces normal to one axis share a map over the same plane (one scan gives both outermost
  // spheres); the x pair and the y pair run on separate threads into their own buffers.
#pragma omp parallel for schedule(static, 1) num_threads(std::min(2, omp_get_max_threads()))
  for (int axis = 0; axis < 2; ++axis)
    map_axis(axis, lo, hi, body_positions, spheres, per_body, radius, scale, scratch_[axis]);

  std::vector<bool> touched(body_positions.size(), false);
  for (int axis = 0; axis < 2; ++axis) {
    const AxisScratch& a = scratch_[axis];
    for (std::size_t b = 0; b < body_positions.size(); ++b) {
      force[b] += a.force[b];
      torque[b] += a.torque[b];
      if (a.touched[b]) touched[b] = true;
    }
    for (int side = 0; side < 2; ++side) {
      stats_.area[2 * axis + side] = a.area[side];
      stats_.load_centre[2 * axis + side] = a.load_centre[side];
    }
    stats_.bridged_area += a.bridged_area;
    stats_.max_depth = std::max(stats_.max_depth, a.max_depth);
  }
  stats_.grains = std::size_t(std::count(touched.begin(), touched.end(), true));
}

void Membrane::bounds(const std::vector<Vec3>& spheres, double radius, Vec3& lo, Vec3& hi) const {
  lo = spheres.front(), hi = lo;
  for (const Vec3& s : spheres) lo = lo.cwiseMin(s), hi = hi.cwiseMax(s);
  lo.array() -= radius;
  hi.array() += radius;
  // The cells lie on a fixed lattice (multiples of the cell size), not on the sample's bounding box:
  // a box that follows the extreme sphere shifts every cell by a little at each update, which flips
  // cells in and out of the spheres' discs and kept a confined sample oscillating for ever.
  for (int k = 0; k < 3; ++k) lo[k] = std::floor(lo[k] / cell_) * cell_;
  // Guard before the threads start (an exception cannot leave a parallel region): a blown-up run's
  // bounding box would size the maps beyond any memory.
  const Vec3 cells = (hi - lo) / cell_;
  if (!lo.allFinite() || !hi.allFinite() ||
      !(cells.x() * cells.z() < kMaxCells && cells.y() * cells.z() < kMaxCells && cells.x() * cells.y() < kMaxCells))
    throw std::runtime_error("the vacuum bag's height map would need " + std::to_string(cells.x() * cells.z()) +
                             " cells: the sample has flown apart (an unstable time step?)");
}

std::pair<double, double> Membrane::end_forces(const std::vector<Vec3>& body_positions,
                                               const std::vector<Vec3>& spheres, std::size_t per_body, double radius,
                                               std::vector<Vec3>& force, const std::vector<double>* scale) const {
  if (spheres.empty()) return {0, 0};
  Vec3 lo, hi;
  bounds(spheres, radius, lo, hi);
  AxisScratch a;
  map_axis(2, lo, hi, body_positions, spheres, per_body, radius, scale, a);
  for (std::size_t b = 0; b < body_positions.size(); ++b) force[b] += a.force[b];
  return {a.area[0], a.area[1]};
}

void Membrane::map_axis(int axis, const Vec3& lo, const Vec3& hi, const std::vector<Vec3>& body_positions,
                        const std::vector<Vec3>& spheres, std::size_t per_body, double radius,
                        const std::vector<double>* scale, AxisScratch& a) const {
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  const double cell_area = cell_ * cell_;
  const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;  // the map's in-plane axes
  const int nu = int(std::ceil((hi[u] - lo[u]) / cell_)), nv = int(std::ceil((hi[v] - lo[v]) / cell_));
  const std::size_t cells = std::size_t(nu) * nv;
  for (int side = 0; side < 2; ++side) {
    a.height[side].assign(cells, -std::numeric_limits<double>::infinity());
    a.owner[side].assign(cells, kNone);
  }
  a.force.assign(body_positions.size(), Vec3::Zero());
  a.torque.assign(body_positions.size(), Vec3::Zero());
  a.touched.assign(body_positions.size(), false);

  // Outermost sphere surface per cell on each side (side 0: +axis, side 1: -axis): every cell a
  // sphere's disc covers, at the sphere's cap height along the outward direction.
  const int reach = int(std::ceil(radius / cell_));
  for (std::size_t s = 0; s < spheres.size(); ++s) {
    const Vec3& c = spheres[s];
    const double r = scale ? radius * (*scale)[s / per_body] : radius;  // scales are at most 1: within `reach`
    const int iu0 = int((c[u] - lo[u]) / cell_), iv0 = int((c[v] - lo[v]) / cell_);
    for (int iu = std::max(0, iu0 - reach); iu <= std::min(nu - 1, iu0 + reach); ++iu) {
      const double du = lo[u] + (iu + 0.5) * cell_ - c[u];
      for (int iv = std::max(0, iv0 - reach); iv <= std::min(nv - 1, iv0 + reach); ++iv) {
        const double dv = lo[v] + (iv + 0.5) * cell_ - c[v];
        const double r2 = r * r - du * du - dv * dv;
        if (r2 < 0) continue;
        const double cap = std::sqrt(r2);
        const std::size_t k = std::size_t(iu) * nv + iv;
        if (c[axis] + cap > a.height[0][k]) a.height[0][k] = c[axis] + cap, a.owner[0][k] = std::uint32_t(s);
        if (-c[axis] + cap > a.height[1][k]) a.height[1][k] = -c[axis] + cap, a.owner[1][k] = std::uint32_t(s);
      }
    }
  }

  a.bridged_area = a.max_depth = 0;
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? 1.0 : -1.0;
    double area = 0, weighted = 0;
    local_envelope(a.height[side], nu, nv, a);
    for (int iu = 0; iu < nu; ++iu) {
      for (int iv = 0; iv < nv; ++iv) {
        const std::size_t k = std::size_t(iu) * nv + iv;
        if (a.owner[side][k] == kNone) continue;
        const double depth = a.envelope[k] - a.height[side][k];
        if (depth > bridge_depth_ && bridge_span_ > 0) {
          a.bridged_area += cell_area;
          continue;
        }
        a.max_depth = std::max(a.max_depth, depth);
        Vec3 f = Vec3::Zero();
        f[axis] = -sign * pressure_ * cell_area;
        Vec3 point;
        point[axis] = sign * a.height[side][k];
        point[u] = lo[u] + (iu + 0.5) * cell_;
        point[v] = lo[v] + (iv + 0.5) * cell_;
        const std::size_t b = a.owner[side][k] / per_body;
        a.force[b] += f;
        a.torque[b] += (point - body_positions[b]).cross(f);
        a.touched[b] = true;
        area += cell_area;
        weighted += cell_area * body_positions[b][axis];
      }
    }
    a.area[side] = area;
    a.load_centre[side] = area > 0 ? weighted / area : 0;
  }
}

namespace {

// out[k] = op over the cells within r of k along one axis of an nu x nv map (0: u, 1: v), the window
// cut at the map's border.
template <class Op>
void running(const std::vector<double>& in, std::vector<double>& out, int nu, int nv, int r, int along, Op op) {
  out.resize(in.size());
  for (int iu = 0; iu < nu; ++iu)
    for (int iv = 0; iv < nv; ++iv) {
      double m = in[std::size_t(iu) * nv + iv];
      if (along == 0)
        for (int i = std::max(0, iu - r); i <= std::min(nu - 1, iu + r); ++i) m = op(m, in[std::size_t(i) * nv + iv]);
      else
        for (int j = std::max(0, iv - r); j <= std::min(nv - 1, iv + r); ++j) m = op(m, in[std::size_t(iu) * nv + j]);
      out[std::size_t(iu) * nv + iv] = m;
    }
}

}  // namespace

// The surface the bag lies on. Two bounds, the lower of which counts:
//  - the closing of the height map by a flat square of half-width r = bridge_span (the highest surface
//    around, then the lowest of those), which fills pits and holes narrower than the square (2 r + 1
//    cells) and leaves wider dents as they are: a bag follows a wide dent;
//  - the map with its enclosed pits filled (priority flood from the map's border: a cell's level is the
//    lowest, over all paths to the border, of the highest surface on the path), which leaves alone bays
//    open to the outside, such as the sample's corners and the notches of its jagged edges: a bag wraps
//    around those. Empty cells count as infinitely deep, so a hole seen through is enclosed by its rim.
// The closing is padded with r empty cells on every side so that windows at the map's border are whole.
void Membrane::local_envelope(const std::vector<double>& height, int nu, int nv, AxisScratch& a) const {
  constexpr double kEmpty = -std::numeric_limits<double>::infinity();
  const int r = bridge_span_ > 0 ? int(std::ceil(bridge_span_ / cell_)) : 0;
  const int pu = nu + 2 * r, pv = nv + 2 * r;
  a.padded.assign(std::size_t(pu) * pv, kEmpty);
  for (int iu = 0; iu < nu; ++iu)
    std::copy_n(height.begin() + std::size_t(iu) * nv, nv, a.padded.begin() + std::size_t(iu + r) * pv + r);
  auto max_op = [](double x, double y) { return std::max(x, y); };
  auto min_op = [](double x, double y) { return std::min(x, y); };
  running(a.padded, a.pass, pu, pv, r, 1, max_op);
  running(a.pass, a.padded, pu, pv, r, 0, max_op);
  running(a.padded, a.pass, pu, pv, r, 1, min_op);  // a map cell's window never reaches past the padding
  running(a.pass, a.padded, pu, pv, r, 0, min_op);

  // Priority flood, lowest level first, from every border cell.
  a.envelope.assign(height.size(), kEmpty);
  std::vector<bool>& done = a.flooded;
  done.assign(height.size(), false);
  // A binary min-heap on the reused a.heap (a std::priority_queue would not give its storage back).
  std::vector<std::pair<double, std::size_t>>& heap = a.heap;
  heap.clear();
  const std::greater<std::pair<double, std::size_t>> lowest_first;
  auto push = [&](double level, std::size_t k) {
    heap.emplace_back(level, k);
    std::push_heap(heap.begin(), heap.end(), lowest_first);
  };
  for (int iu = 0; iu < nu; ++iu)
    for (int iv = 0; iv < nv; ++iv)
      if (iu == 0 || iv == 0 || iu == nu - 1 || iv == nv - 1) {
        const std::size_t k = std::size_t(iu) * nv + iv;
        push(height[k], k);
        done[k] = true;
      }
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), lowest_first);
    const auto [level, k] = heap.back();
    heap.pop_back();
    a.envelope[k] = level;
    const int iu = int(k / nv), iv = int(k % nv);
    const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
    for (int n = 0; n < 4; ++n) {
      const int ju = iu + du[n], jv = iv + dv[n];
      if (ju < 0 || jv < 0 || ju >= nu || jv >= nv) continue;
      const std::size_t m = std::size_t(ju) * nv + jv;
      if (done[m]) continue;
      done[m] = true;
      push(std::max(level, height[m]), m);
    }
  }
  for (int iu = 0; iu < nu; ++iu)
    for (int iv = 0; iv < nv; ++iv) {
      double& e = a.envelope[std::size_t(iu) * nv + iv];
      e = std::min(e, a.padded[std::size_t(iu + r) * pv + iv + r]);
    }
}

void Membrane::save(CheckpointWriter& w) const {
  w.section("membrane");
  w.value(pressure_);
  w.value(stats_);
}

void Membrane::restore(CheckpointReader& r) {
  r.section("membrane");
  r.value(pressure_);
  r.value(stats_);
}

}  // namespace granulab
