#include "engine/crystal/imperfections.h"

#include <algorithm>
#include <cmath>

namespace granulab {

namespace {

// A small, fully specified generator (SplitMix64), so that a seed gives the same crystal on any
// platform and standard library (std::normal_distribution's algorithm is the library's choice).
struct Stream {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return (double(next() >> 11) + 0.5) * 0x1.0p-53; }  // in (0, 1)
  double normal() {                                                      // Box-Muller; one of the pair is enough here
    const double u = uniform(), v = uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * M_PI * v);
  }
};

// Support of the clump along unit `n` (body frame): the farthest sphere surface (m).
double support(const std::vector<Vec3>& offsets, double radius, const Vec3& n) {
  double h = -1e300;
  for (const Vec3& o : offsets) h = std::max(h, o.dot(n));
  return h + radius;
}

}  // namespace

double fit_scale(const GrainTemplate& grain, const Quat& rotation) {
  std::vector<Vec3> turned;
  for (const Vec3& o : grain.offsets()) turned.push_back(rotation * o);
  double scale = 1;
  for (const Face& f : grain.solid().faces())
    scale =
        std::min(scale, support(grain.offsets(), grain.radius(), f.normal) / support(turned, grain.radius(), f.normal));
  return scale;
}

double min_scale_bound(const ImperfectionParams& p, const GrainTemplate& grain) {
  if (!p.any()) return 1;
  double h0 = 1e300, reach = 0;
  for (const Face& f : grain.solid().faces()) h0 = std::min(h0, support(grain.offsets(), grain.radius(), f.normal));
  for (const Vec3& o : grain.offsets()) reach = std::max(reach, o.norm());
  const double theta = 4 * p.misorientation * M_PI / 180;
  return std::max(0.5, 1 - 5 * p.size_dispersion) * h0 / (h0 + reach * theta);
}

std::vector<GrainImperfection> draw_imperfections(const ImperfectionParams& p, const CrystalLattice& lattice,
                                                  const GrainTemplate& grain) {
  std::vector<GrainImperfection> out(lattice.sites.size());
  if (!p.any()) return out;
  const double sigma_r = p.misorientation * M_PI / 180;
  for (std::size_t k = 0; k < out.size(); ++k) {
    // One stream per grain, from the seed and the grain's id: knocking grains out leaves the others as drawn.
    Stream s{p.seed * 0x2545f4914f6cdd1dULL ^ (std::uint64_t(value(lattice.sites[k].id)) + 1) * 0x9e3779b97f4a7c15ULL};
    const double z = s.normal();
    const Vec3 w(s.normal(), s.normal(), s.normal());
    GrainImperfection& g = out[k];
    g.scale = std::max(0.5, 1 - p.size_dispersion * std::abs(z));
    if (sigma_r > 0) {
      const Vec3 rotation_vector = w * (sigma_r / std::sqrt(3.0));
      const double angle = rotation_vector.norm();
      if (angle > 0) g.rotation = Quat(Eigen::AngleAxisd(angle, rotation_vector / angle));
      g.scale *= fit_scale(grain, g.rotation);
    }
  }
  return out;
}

}  // namespace granulab
