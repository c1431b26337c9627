#include "engine/contact/neighbor_list.h"

#include <algorithm>
#include <cmath>
#include <omp.h>
#include <stdexcept>

namespace granulab {

NeighborList::NeighborList(const std::vector<Vec3>& offsets, double diameter, double skin)
    : offsets_(offsets), radius_(diameter / 2), skin_(skin), cutoff_(diameter + skin) {
  if (!(skin > 0)) throw std::invalid_argument("neighbour skin must be > 0");
  double r = 0;
  for (const Vec3& o : offsets_) r = std::max(r, o.norm());
  grain_cutoff_ = 2 * r + cutoff_;
  grid_ = TemplateGrid(offsets_, cutoff_);
}

void NeighborList::rebuild(const Bodies& bodies, const std::vector<Vec3>& sphere_positions,
                           const std::vector<Wall>& walls) {
  std::swap(pairs_, old_pairs_);
  std::swap(keys_, old_keys_);
  std::swap(history_, old_history_);
  std::swap(wall_keys_, old_wall_keys_);
  std::swap(wall_history_, old_wall_history_);
  broad_phase(bodies);
  narrow_phase(bodies);
  wall_phase(bodies, sphere_positions, walls);
}

// Grain pairs whose centres are closer than grain_cutoff_, from a cell grid of that size:
// each grain only looks at the 27 cells around its own.
void NeighborList::broad_phase(const Bodies& bodies) {
  pairs_.clear();
  const std::size_t n = bodies.size();
  if (n < 2) return;
  Vec3 lo = bodies.position.front();
  for (const Vec3& x : bodies.position) lo = lo.cwiseMin(x);
  const double inv = 1 / grain_cutoff_;
  auto cell = [&](const Vec3& x) {
    const Vec3 f = (x - lo) * inv;
    return Eigen::Vector3i(int(f.x()), int(f.y()), int(f.z()));
  };
  auto pack = [](const Eigen::Vector3i& c) {
    return std::uint64_t(c.x()) << 42 | std::uint64_t(c.y()) << 21 | std::uint64_t(c.z());
  };
  // Grains sorted by cell key; a cell's grains are found by binary search.
  auto& sorted = cell_keys_;
  sorted.resize(n);
  for (std::size_t b = 0; b < n; ++b) sorted[b] = {pack(cell(bodies.position[b])), BodyId(b)};
  std::sort(sorted.begin(), sorted.end());
  const double cut2 = grain_cutoff_ * grain_cutoff_;
  for (std::size_t a = 0; a < n; ++a) {
    const Eigen::Vector3i c = cell(bodies.position[a]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3i nc = c + Eigen::Vector3i(dx, dy, dz);
          if ((nc.array() < 0).any()) continue;
          const std::uint64_t key = pack(nc);
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(key, BodyId(0)));
          for (; it != sorted.end() && it->first == key; ++it) {
            const BodyId b = it->second;
            if (b <= a) continue;
            if ((bodies.position[b] - bodies.position[a]).squaredNorm() < cut2)
              pairs_.push_back({BodyId(a), b, 0, 0});
          }
        }
  }
  std::sort(pairs_.begin(), pairs_.end(),
            [](const BodyPairSpan& p, const BodyPairSpan& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; });
}

void NeighborList::narrow_phase(const Bodies& bodies) {
  const long n_pairs = long(pairs_.size());
  const int n_threads = omp_get_max_threads();
  thread_keys_.resize(n_threads);
  pair_thread_.resize(n_pairs);
  pair_offset_.resize(n_pairs);
  double reach = 0;
  for (const Vec3& o : offsets_) reach = std::max(reach, o.norm());
  reach += cutoff_;

#pragma omp parallel
  {
    const int t = omp_get_thread_num();
    std::vector<std::uint32_t>& out = thread_keys_[t];
    out.clear();
#pragma omp for schedule(dynamic, 4)
    for (long p = 0; p < n_pairs; ++p) {
      BodyPairSpan& gp = pairs_[p];
      const Quat qa_inv = bodies.orientation[gp.a].conjugate();
      const Mat3 r_ab = (qa_inv * bodies.orientation[gp.b]).toRotationMatrix();
      const Vec3 t_ab = qa_inv * (bodies.position[gp.b] - bodies.position[gp.a]);
      const std::size_t begin = out.size();
      for (std::size_t j = 0; j < offsets_.size(); ++j) {
        const Vec3 pj = r_ab * offsets_[j] + t_ab;
        if (pj.squaredNorm() > reach * reach) continue;
        grid_.for_each_near(pj, cutoff_, [&](LocalSphereId i) {
          out.push_back(sphere_pair_key(i, LocalSphereId(j)));
        });
      }
      std::sort(out.begin() + begin, out.end());
      pair_thread_[p] = std::uint32_t(t);
      pair_offset_[p] = std::uint32_t(begin);
      gp.count = std::uint32_t(out.size() - begin);
    }
  }

  std::uint32_t total = 0;
  for (BodyPairSpan& gp : pairs_) gp.first = total, total += gp.count;
  keys_.resize(total);
  history_.resize(total);
#pragma omp parallel for schedule(static)
  for (long p = 0; p < n_pairs; ++p) {
    const BodyPairSpan& gp = pairs_[p];
    const std::uint32_t* src = thread_keys_[pair_thread_[p]].data() + pair_offset_[p];
    std::copy(src, src + gp.count, keys_.begin() + gp.first);
  }
  // Drop grain pairs with no sphere pair: they cost a loop iteration every step for nothing.
  pairs_.erase(std::remove_if(pairs_.begin(), pairs_.end(), [](const BodyPairSpan& gp) { return gp.count == 0; }),
               pairs_.end());

  // Carry history: walk old and new grain pairs in (a, b) order, and inside a shared grain pair
  // walk both sorted key blocks.
  std::size_t po = 0;
  for (const BodyPairSpan& gp : pairs_) {
    while (po < old_pairs_.size() &&
           (old_pairs_[po].a < gp.a || (old_pairs_[po].a == gp.a && old_pairs_[po].b < gp.b)))
      ++po;
    const bool shared = po < old_pairs_.size() && old_pairs_[po].a == gp.a && old_pairs_[po].b == gp.b;
    std::uint32_t ko = shared ? old_pairs_[po].first : 0;
    const std::uint32_t ko_end = shared ? ko + old_pairs_[po].count : 0;
    for (std::uint32_t k = gp.first; k < gp.first + gp.count; ++k) {
      while (ko < ko_end && old_keys_[ko] < keys_[k]) ++ko;
      history_.set(k, (ko < ko_end && old_keys_[ko] == keys_[k]) ? old_history_.get(ko) : Vec3::Zero());
    }
  }
}

void NeighborList::wall_phase(const Bodies& bodies, const std::vector<Vec3>& sphere_positions,
                              const std::vector<Wall>& walls) {
  wall_keys_.clear();
  const std::size_t per_body = offsets_.size();
  double reach = 0;
  for (const Vec3& o : offsets_) reach = std::max(reach, o.norm());
  const double sphere_reach = radius_ + skin_;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      if (walls[w].distance(bodies.position[b]) > reach + sphere_reach) continue;
      for (std::size_t i = 0; i < per_body; ++i) {
        const std::size_t s = b * per_body + i;
        if (walls[w].distance(sphere_positions[s]) < sphere_reach)
          wall_keys_.push_back(wall_pair_key(std::uint32_t(w), std::uint32_t(s)));
      }
    }
  }
  wall_history_.resize(wall_keys_.size());
  std::size_t ko = 0;
  for (std::size_t k = 0; k < wall_keys_.size(); ++k) {
    while (ko < old_wall_keys_.size() && old_wall_keys_[ko] < wall_keys_[k]) ++ko;
    wall_history_[k] =
        (ko < old_wall_keys_.size() && old_wall_keys_[ko] == wall_keys_[k]) ? old_wall_history_[ko] : Vec3::Zero();
  }
}

}  // namespace granulab
