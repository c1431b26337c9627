#include "engine/crystal/crystal_snapshot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>


#include "engine/analysis/grain_kinematics.h"
#include "engine/analysis/slip_bands.h"

namespace granulab {

void CrystalReference::take(const CrystalSample& sample) {
  const Bodies& b = sample.world().bodies();
  position = b.position;
  orientation = b.orientation;
  interfaces = neighbour_pairs(position, 1.1 * sample.face_neighbour_distance());
}

GrainSnapshot crystal_snapshot(const CrystalSample& sample, const CrystalReference& ref, double strain) {
  const World& world = sample.world();
  const std::vector<GrainId>& ids = sample.grain_ids();
  const Bodies& b = world.bodies();
  GrainSnapshot s;
  s.strain = strain;
  s.step = world.steps();
  s.grain_shape = sample.grain().geometry().shape;
  s.grain_size = sample.params().grain.size;
  s.layer_spacing = sample.lattice().period.y();
  s.layer_planes = layer_planes(sample.lattice());
  s.edge_spheres = sample.params().grain.edge_spheres;
  s.sphere_overlap = sample.params().grain.overlap;
  s.id = ids;
  s.position = b.position;
  s.orientation = b.orientation;
  s.displacement.resize(b.size());
  for (std::size_t i = 0; i < b.size(); ++i) s.displacement[i] = b.position[i] - ref.position[i];
  s.scale = b.scale;
  // The contact network: the grain pairs whose spheres touch now (a pair's force is exactly zero otherwise).
  const auto& pairs = world.neighbors().body_pairs();
  const auto& forces = world.pair_forces();
  for (std::size_t p = 0; p < pairs.size() && p < forces.size(); ++p) {
    if (forces[p].isZero()) continue;
    s.contacts.push_back({ids[pairs[p].a], ids[pairs[p].b]});
    s.contact_force.push_back(forces[p]);
  }
  s.penetration = world.overlap_sums();
  double mean = 0;
  for (double d : s.penetration) mean += d;
  mean /= s.penetration.size();
  for (double d : s.penetration) s.penetration_ratio.push_back(mean > 0 ? d / mean : 0);
  for (const LocalStrain& e : local_strains(ref.position, b.position, ref.interfaces)) {
    s.gamma_max.push_back(e.max_shear);
    s.equivalent_strain.push_back(e.equivalent);
    s.d2min.push_back(e.d2min);
  }
  for (std::size_t i = 0; i < b.size(); ++i) {
    const Misorientation m = misorientation(ref.orientation[i], b.orientation[i]);
    s.misorientation.push_back(m.angle);
    s.misorientation_axis.push_back(m.axis);
  }
  for (const auto& [p, q] : ref.interfaces) s.interfaces.push_back({ids[p], ids[q]});
  s.sliding = interface_sliding(ref.position, ref.orientation, b.position, b.orientation, ref.interfaces);
  s.crystal_orientation = sample.lattice().orientation;
  s.slip_bands = find_slip_bands(s, sample.params().lattice);
  return s;
}

void snapshot_marks(CheckpointWriter& a, const std::vector<GrainSnapshot>& s) {
  a.value(std::uint64_t(s.size()));
  for (const GrainSnapshot& g : s) a.value(g.strain), a.value(g.step), a.values(g.slip_bands);
}

void snapshot_marks(CheckpointReader& a, std::vector<GrainSnapshot>& s) {
  s.resize(a.value<std::uint64_t>());
  for (GrainSnapshot& g : s) a.value(g.strain), a.value(g.step), a.values(g.slip_bands);
}

std::string missed_snapshots_warning(const std::vector<double>& asked, const std::vector<GrainSnapshot>& taken,
                                     double reached) {
  std::string missed;
  std::size_t count = 0;
  for (double e : asked) {
    const bool got = std::any_of(taken.begin(), taken.end(),
                                 [&](const GrainSnapshot& s) { return std::abs(std::abs(s.strain) - e) <= 1e-12; });
    if (got) continue;
    char text[32];
    std::snprintf(text, sizeof text, "%s%g", count ? ", " : "", e);
    missed += text, ++count;
  }
  if (!count) return "";
  char tail[96];
  std::snprintf(tail, sizeof tail, "; the largest strain the run reached was %g", reached);
  return "output.snapshot_strains " + missed +
         (count == 1 ? " was" : " were") + " never reached, so no snapshot was taken there" + tail;
}

}  // namespace granulab
