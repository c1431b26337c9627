// A crystal experiment's grain snapshots (grain_snapshot.h), measured from where the grains stood when its
// loading began: displacements, the local strains over the face-neighbour pairs of that state, and the sliding
// of those interfaces. Shared by the crystal experiments, whatever they load.
#pragma once

#include <vector>

#include "engine/analysis/grain_snapshot.h"
#include "engine/core/checkpoint.h"
#include "engine/crystal/crystal_sample.h"

namespace granulab {

/// The reference state: every grain's pose and the interfaces between face neighbours then.
struct CrystalReference {
  std::vector<Vec3> position;
  std::vector<Quat> orientation;
  std::vector<BodyPair> interfaces;
  /// The sample as it is now.
  void take(const CrystalSample& sample);
};

/// The snapshot of the sample as it is, labelled with `strain` (the experiment's own: axial or shear).
GrainSnapshot crystal_snapshot(const CrystalSample& sample, const CrystalReference& reference, double strain);

/// Checkpoints keep the snapshots taken as (strain, step, slip bands) only: the summary lists no more, and the sink
/// has the rest.
void snapshot_marks(CheckpointWriter& a, const std::vector<GrainSnapshot>& s);
/// The warning a run's summary gives when some of the `asked` snapshot strains were never reached (a loading program
/// that stays below them, or a run cut short): which, and the largest strain the run reached; "" when all were taken.
std::string missed_snapshots_warning(const std::vector<double>& asked, const std::vector<GrainSnapshot>& taken,
                                     double reached);
void snapshot_marks(CheckpointReader& a, std::vector<GrainSnapshot>& s);

}  // namespace granulab
