// A snapshot's lattice measures from its reference state (position - displacement): the nearest-neighbour
// distance and the layers normal to y (the section pictures' slices; layer 0 is the front face, lowest y,
// which the DIC-like map looks at).
#pragma once

#include <vector>

#include "engine/analysis/grain_snapshot.h"

namespace granulab {

/// The nearest-neighbour distance of the reference state: the median over the interfaces (m); 0 without any.
double neighbour_distance(const GrainSnapshot& s);

struct SnapshotLayers {
  std::vector<int> layer;  ///< per grain, 0 = lowest reference y
  int count = 0;
};

/// The planes of equal reference y: a grain whose y lies within a tenth of the mean layer spacing of the previous
/// one's shares its layer (HCP's planes are unevenly spaced, so y is not rounded to a period). The spacing is the
/// snapshot's, or for snapshots stored before lattices were a choice the paper's {111} one, neighbour x sqrt(2/3).
SnapshotLayers snapshot_layers(const GrainSnapshot& s);

}  // namespace granulab
