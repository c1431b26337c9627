// A section through a crystal snapshot, like the paper's Figs. 8 and 11: the grains of one layer normal to y
// ({111} for the paper's crystal; the snapshot names its planes), the plane of the page x-z, the compression
// axis z vertical, each drawn as its grain's cross-section through its centre (the rhombic dodecahedron's, or
// the snapshot's grain shape), rotated as the grain is, coloured by a per-grain
// field with a colour bar; interfaces of the layer that slid more than twice the mean sliding are
// drawn as black lines (Fig. 11b). Sizes come from the snapshot itself (its reference neighbour
// distance), so no spec is needed.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>

#include "engine/analysis/grain_snapshot.h"

namespace granulab::pictures {

enum class Field { penetration_ratio, gamma_max, equivalent_strain, displacement, d2min, misorientation };

/// "penetration_ratio", "gamma_max", "equivalent_strain", "displacement", "d2min" or "misorientation"; nullopt for anything
/// else.
std::optional<Field> parse_field(const std::string& name);
/// The layers normal to y of the snapshot ({111} for the paper's crystal) (at the reference state), 0 = the front face (lowest y).
int layer_count(const GrainSnapshot& s);
/// The SVG document for `layer` (default: the middle layer, (layers - 1) / 2). Throws
/// std::out_of_range naming the valid layers when `layer` is not one of them, std::invalid_argument for a field
/// the snapshot was stored without (d2min and misorientation of snapshots older than them).
std::string section_svg(const GrainSnapshot& s, Field field, std::optional<int> layer, const std::string& title);

}  // namespace granulab::pictures
