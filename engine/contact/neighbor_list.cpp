#include "engine/contact/neighbor_list.h"

#include <algorithm>
#include <cmath>
#include <omp.h>
#include <stdexcept>

namespace granulab {

namespace {
constexpr std::uint32_t kNoPair = 0xffffffffu;
// A drifted pair triggers an update; every pair beyond this share of the skin is searched in the same
// update, so that pairs drifting together are not searched one update each (each update also copies
// every block once).
constexpr double kRefreshShare = 0.5;
}  // namespace

NeighborList::NeighborList(const std::vector<Vec3>& offsets, double diameter, double skin, double min_scale)
    : offsets_(offsets), radius_(diameter / 2), skin_(skin), cutoff_(diameter + skin) {
  if (!(skin > 0)) throw std::invalid_argument("neighbour skin must be > 0");
  reach_ = 0;
  for (const Vec3& o : offsets_) reach_ = std::max(reach_, o.norm());
  grain_cutoff_ = 2 * reach_ + cutoff_;
  // A sphere diameter of margin: a grain crosses half of it in thousands of steps under the platens,
  // and it adds no new neighbours to a face-to-face packing (the next shell is ~2 d further out).
  margin_ = std::max(diameter, 2 * skin);
  // A scaled grain a is searched in its template's frame, with the cutoff over its scale.
  grid_ = TemplateGrid(offsets_, cutoff_ / min_scale);
  for (const Vec3& o : offsets_) offset_x_.push_back(o.x()), offset_y_.push_back(o.y()), offset_z_.push_back(o.z());
}

NeighborUpdate NeighborList::update(const Bodies& bodies, const std::vector<Wall>& walls) {
  NeighborUpdate u;
  const std::size_t n_old = pairs_.size();
  if (!built_ || broad_position_.size() != bodies.size() || broad_phase_due(bodies)) {
    retire_candidates();
    broad_phase(bodies);
    // Every pair is searched (this happens once per half margin of travel); pairs that were already
    // watched carry their histories over.
    old_index_.assign(pairs_.size(), kNoPair);
    std::size_t po = 0;
    for (std::size_t p = 0; p < pairs_.size(); ++p) {
      const BodyPairSpan& gp = pairs_[p];
      while (po < old_pairs_.size() &&
             (old_pairs_[po].a < gp.a || (old_pairs_[po].a == gp.a && old_pairs_[po].b < gp.b)))
        ++po;
      if (po < old_pairs_.size() && old_pairs_[po].a == gp.a && old_pairs_[po].b == gp.b)
        old_index_[p] = std::uint32_t(po);
    }
    search_.assign(pairs_.size(), 1);
    frame_t_.resize(pairs_.size());
    frame_q_.resize(pairs_.size());
    search_and_merge(bodies);
    broad_position_ = bodies.position;
    u.broad = true;
    u.pairs_searched = std::uint32_t(pairs_.size());
    built_ = true;
  } else if (n_old > 0 && mark_drifted(bodies, skin_) > 0) {
    u.pairs_searched = mark_drifted(bodies, kRefreshShare * skin_);
    retire_candidates();
    pairs_ = old_pairs_;
    old_index_.resize(n_old);
    for (std::size_t p = 0; p < n_old; ++p) old_index_[p] = std::uint32_t(p);
    search_and_merge(bodies);
  }
  if (u.broad || wall_phase_due(bodies, walls)) {
    wall_phase(bodies, walls);
    u.walls = true;
  }
  return u;
}

// The current lists become the old ones that search_and_merge() copies and merges from.
void NeighborList::retire_candidates() {
  std::swap(pairs_, old_pairs_);
  std::swap(keys_, old_keys_);
  std::swap(history_, old_history_);
}

bool NeighborList::broad_phase_due(const Bodies& bodies) const {
  const double limit2 = margin_ * margin_ / 4;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if ((bodies.position[b] - broad_position_[b]).squaredNorm() >= limit2) return true;
  return false;
}

// A sphere's distance to a plane wall changes by at most the normal part of the grain's and the wall's
// relative displacement plus r_max |R - R0| = 2 r_max sin(theta/2) for the grain's rotation theta.
bool NeighborList::wall_phase_due(const Bodies& bodies, const std::vector<Wall>& walls) const {
  if (wall_point_.size() != walls.size() || wall_body_position_.size() != bodies.size()) return true;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const double rot = 2 * reach_ * (wall_body_orientation_[b].conjugate() * bodies.orientation[b]).vec().norm();
    const Vec3 dx = bodies.position[b] - wall_body_position_[b];
    for (std::size_t w = 0; w < walls.size(); ++w)
      if (std::abs((dx - (walls[w].point - wall_point_[w])).dot(walls[w].normal)) + rot >= skin_) return true;
  }
  return false;
}

// Drift of grain pair (a, b) since its search: the largest displacement of a sphere of b in a's frame,
// bounded by |t - t_ref| + r_max |R - R_ref| (|R - R_ref| = 2 sin(theta/2), theta the angle of
// q_ref^-1 q).
std::uint32_t NeighborList::mark_drifted(const Bodies& bodies, double threshold) {
  const long n_pairs = long(pairs_.size());
  search_.resize(n_pairs);
  std::uint32_t marked = 0;
#pragma omp parallel for schedule(static) reduction(+ : marked) if (n_pairs >= 512)
  for (long p = 0; p < n_pairs; ++p) {
    const BodyPairSpan& gp = pairs_[p];
    const Quat qa_inv = bodies.orientation[gp.a].conjugate();
    const Vec3 t = qa_inv * (bodies.position[gp.b] - bodies.position[gp.a]);
    const Quat dq = frame_q_[p].conjugate() * (qa_inv * bodies.orientation[gp.b]);
    const double drift = (t - frame_t_[p]).norm() + 2 * reach_ * dq.vec().norm();
    search_[p] = drift >= threshold;
    marked += search_[p];
  }
  return marked;
}

// Grain pairs whose centres are closer than the broad cutoff, from a cell grid of that size:
// each grain only looks at the 27 cells around its own.
void NeighborList::broad_phase(const Bodies& bodies) {
  pairs_.clear();
  const std::size_t n = bodies.size();
  if (n < 2) return;
  const double broad = broad_cutoff();
  Vec3 lo = bodies.position.front();
  for (const Vec3& x : bodies.position) lo = lo.cwiseMin(x);
  const double inv = 1 / broad;
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
  const double cut2 = broad * broad;
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
            if ((bodies.position[b] - bodies.position[a]).squaredNorm() < cut2) pairs_.push_back({BodyId(a), b, 0, 0});
          }
        }
  }
  std::sort(pairs_.begin(), pairs_.end(),
            [](const BodyPairSpan& p, const BodyPairSpan& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; });
}

// The sphere pairs of the marked grain pairs (search_), then the new layout: a searched pair merges its
// new sorted block with its old one (old_index_: the pair's index in old_pairs_, or kNoPair) to carry the
// histories; the others keep their block and history as they were.
//
// Only b's spheres on the side facing a are looked up: with u the unit vector from x_a to x_b (a's frame),
// every sphere of a has u . o_i <= h_a = max_i u . o_i, so a sphere of b can be within the cutoff of one
// only if u . p_j <= h_a + cutoff, i.e. (R_ab^T u) . o_j <= h_a + cutoff - |t_ab|. Two dot products per
// sphere, vectorised over the component arrays, spare most grid lookups of face-to-face neighbours (the
// candidates found are exactly the same).
void NeighborList::search_and_merge(const Bodies& bodies) {
  const std::vector<std::uint32_t>& old_index = old_index_;
  const long n_pairs = long(pairs_.size());
  const int n_threads = omp_get_max_threads();
  thread_keys_.resize(n_threads);
  pair_thread_.resize(n_pairs);
  pair_offset_.resize(n_pairs);
  const std::size_t n_spheres = offsets_.size();
  const double *ox = offset_x_.data(), *oy = offset_y_.data(), *oz = offset_z_.data();

#pragma omp parallel
  {
    const int t = omp_get_thread_num();
    std::vector<std::uint32_t>& out = thread_keys_[t];
    out.clear();
#pragma omp for schedule(dynamic, 4)
    for (long p = 0; p < n_pairs; ++p) {
      BodyPairSpan& gp = pairs_[p];
      if (!search_[p]) {
        gp.count = old_pairs_[old_index[p]].count;
        continue;
      }
      const Quat qa_inv = bodies.orientation[gp.a].conjugate();
      const Quat q_ab = qa_inv * bodies.orientation[gp.b];
      const Vec3 t_ab = qa_inv * (bodies.position[gp.b] - bodies.position[gp.a]);
      frame_t_[p] = t_ab;
      frame_q_[p] = q_ab;
      const std::size_t begin = out.size();
      pair_thread_[p] = std::uint32_t(t);
      pair_offset_[p] = std::uint32_t(begin);
      const double dist = t_ab.norm();
      if (dist >= grain_cutoff_) {  // watched only: no sphere of b within the cutoff of one of a
        gp.count = 0;
        continue;
      }
      const Mat3 r_ab = q_ab.toRotationMatrix();
      const Vec3 u = dist > 0 ? Vec3(t_ab / dist) : Vec3::UnitX();
      const Vec3 ub = r_ab.transpose() * u;
      double h_a = -1e300;
#pragma omp simd reduction(max : h_a)
      for (std::size_t i = 0; i < n_spheres; ++i) h_a = std::max(h_a, u.x() * ox[i] + u.y() * oy[i] + u.z() * oz[i]);
      const double sa = bodies.scale[gp.a], sb = bodies.scale[gp.b];
      if (sa == 1 && sb == 1) {
        // Without a direction (coincident centres) every sphere is looked up.
        const double limit = dist > 0 ? h_a + cutoff_ - dist : 1e300;
        for (std::size_t j = 0; j < n_spheres; ++j) {
          if (ub.x() * ox[j] + ub.y() * oy[j] + ub.z() * oz[j] > limit) continue;
          const Vec3 pj = r_ab * offsets_[j] + t_ab;
          grid_.for_each_near(pj, cutoff_,
                              [&](LocalSphereId i) { out.push_back(sphere_pair_key(i, LocalSphereId(j))); });
        }
      } else {
        // Scaled grains: a's spheres at sa o_i, b's at sb R_ab o_j + t_ab, candidates within r (sa + sb) + skin;
        // looked up in a's template frame (divided by sa).
        const double cutoff = radius_ * (sa + sb) + skin_;
        const double limit = dist > 0 ? (sa * h_a + cutoff - dist) / sb : 1e300;
        for (std::size_t j = 0; j < n_spheres; ++j) {
          if (ub.x() * ox[j] + ub.y() * oy[j] + ub.z() * oz[j] > limit) continue;
          const Vec3 pj = (sb * (r_ab * offsets_[j]) + t_ab) / sa;
          grid_.for_each_near(pj, cutoff / sa,
                              [&](LocalSphereId i) { out.push_back(sphere_pair_key(i, LocalSphereId(j))); });
        }
      }
      std::sort(out.begin() + begin, out.end());
      gp.count = std::uint32_t(out.size() - begin);
    }
  }

  std::uint32_t total = 0;
  for (BodyPairSpan& gp : pairs_) gp.first = total, total += gp.count;
  keys_.resize(total);
  history_.resize(total);
#pragma omp parallel for schedule(dynamic, 16)
  for (long p = 0; p < n_pairs; ++p) {
    const BodyPairSpan& gp = pairs_[p];
    const std::uint32_t o = old_index[p];
    const std::uint32_t ko_begin = o != kNoPair ? old_pairs_[o].first : 0;
    const std::uint32_t ko_end = o != kNoPair ? ko_begin + old_pairs_[o].count : 0;
    if (!search_[p]) {
      std::copy(old_keys_.begin() + ko_begin, old_keys_.begin() + ko_end, keys_.begin() + gp.first);
      std::copy(old_history_.x.begin() + ko_begin, old_history_.x.begin() + ko_end, history_.x.begin() + gp.first);
      std::copy(old_history_.y.begin() + ko_begin, old_history_.y.begin() + ko_end, history_.y.begin() + gp.first);
      std::copy(old_history_.z.begin() + ko_begin, old_history_.z.begin() + ko_end, history_.z.begin() + gp.first);
      if (history_.bonds)
        std::copy(old_history_.bond.begin() + ko_begin, old_history_.bond.begin() + ko_end,
                  history_.bond.begin() + gp.first);
      continue;
    }
    const std::uint32_t* src = thread_keys_[pair_thread_[p]].data() + pair_offset_[p];
    std::copy(src, src + gp.count, keys_.begin() + gp.first);
    // Walk both sorted blocks: a sphere pair that stays a candidate keeps its history.
    std::uint32_t ko = ko_begin;
    for (std::uint32_t k = gp.first; k < gp.first + gp.count; ++k) {
      while (ko < ko_end && old_keys_[ko] < keys_[k]) ++ko;
      if (ko < ko_end && old_keys_[ko] == keys_[k])
        history_.take(k, old_history_, ko);
      else
        history_.clear(k);
    }
  }
}

// Sphere centres within radius + skin of a wall, computed from the poses for the grains within reach.
void NeighborList::wall_phase(const Bodies& bodies, const std::vector<Wall>& walls) {
  std::swap(wall_keys_, old_wall_keys_);
  std::swap(wall_history_, old_wall_history_);
  wall_keys_.clear();
  const std::size_t per_body = offsets_.size();
  const double sphere_reach = radius_ + skin_;
  for (std::size_t w = 0; w < walls.size(); ++w) {
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      if (walls[w].distance(bodies.position[b]) > reach_ + sphere_reach) continue;
      const Mat3 r = bodies.orientation[b].toRotationMatrix();
      for (std::size_t i = 0; i < per_body; ++i)
        if (walls[w].distance(bodies.position[b] + r * offsets_[i]) < sphere_reach)
          wall_keys_.push_back(wall_pair_key(std::uint32_t(w), std::uint32_t(b * per_body + i)));
    }
  }
  wall_history_.resize(wall_keys_.size());
  std::size_t ko = 0;
  for (std::size_t k = 0; k < wall_keys_.size(); ++k) {
    while (ko < old_wall_keys_.size() && old_wall_keys_[ko] < wall_keys_[k]) ++ko;
    wall_history_[k] =
        (ko < old_wall_keys_.size() && old_wall_keys_[ko] == wall_keys_[k]) ? old_wall_history_[ko] : Vec3::Zero();
  }
  wall_body_position_ = bodies.position;
  wall_body_orientation_ = bodies.orientation;
  wall_point_.resize(walls.size());
  for (std::size_t w = 0; w < walls.size(); ++w) wall_point_[w] = walls[w].point;
}

}  // namespace granulab
