// What digital image correlation would see of a snapshot (the paper's Fig. 12): the front face (the layer of
// lowest reference y, the face a camera films) resampled on a regular grid in the reference plane x-z. At each
// node the grains of that face within a subset radius give, by weighted least squares, an affine displacement
// field u(X, Z) = u0 + dU/dX (X - Xn) + dU/dZ (Z - Zn) of all three components (stereo DIC measures the
// out-of-plane one too), hence the in-plane Green-Lagrange strain E = (F^T F - I) / 2 with F the 3 x 2 gradient of
// x = X + u: exactly the crystal's strain for any uniform deformation. Cost: per node, the grains of the face
// within the subset (a bucket grid), so O(nodes x subset); well under a millisecond for the reference crystal.
#pragma once

#include <vector>

#include "engine/analysis/grain_snapshot.h"

namespace granulab {

struct DicMap {
  double step = 0;           ///< grid spacing (m)
  double subset = 0;         ///< subset radius: grains farther from a node do not count (m)
  double x0 = 0, z0 = 0;     ///< node (i, k) lies at (x0 + i step, z0 + k step), reference coordinates (m)
  double y = 0;              ///< the face's mean reference y (m)
  int nx = 0, nz = 0;        ///< nodes along x and z
  std::size_t grains = 0;    ///< grains of the face (-)
  // Per node, index k * nx + i; NaN where no grain lies within a neighbour distance (outside the sample, holes).
  std::vector<double> ux, uy, uz;     ///< displacement (m)
  std::vector<double> exx, ezz, exz;  ///< in-plane Green-Lagrange strain, extension positive (-)
  std::vector<double> gamma_max;      ///< in-plane maximum shear strain sqrt(((exx - ezz)/2)^2 + exz^2) (-)
};

/// The map at grid step `step` (m, > 0) with subset radius `subset` (m; 0: the larger of the step and 1.25
/// neighbour distances, so every node inside the face has the grains of a hexagon around it). Throws
/// std::invalid_argument when the snapshot has no grains or the grid would exceed `max_nodes`.
DicMap dic_map(const GrainSnapshot& s, double step, double subset = 0, std::size_t max_nodes = 4000000);

}  // namespace granulab
