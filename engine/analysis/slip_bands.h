// Slip bands found and named (docs/model.md, "Slip bands"): of a snapshot's interfaces, those sliding more than
// `threshold` times the mean (the paper's Fig. 11 rule), grouped into bands on planes, each fitted and named by the
// nearest lattice plane, with its slip vector, slip direction and dilation, so that "two crossing (-2 1 1) and
// (-1 2 -1) bands" is a number a sweep can compare rather than a reading of a picture.
#pragma once

#include <vector>

#include "engine/analysis/grain_snapshot.h"
#include "engine/crystal/lattice_type.h"
#include "engine/framework/summary_writer.h"

namespace granulab {

struct SlipBandOptions {
  double threshold = 2;        ///< an interface slides when its sliding exceeds this times the mean (-)
  double noise = 1e-3;         ///< ... and this times the neighbour distance (-)
  int max_index = 3;           ///< lattice planes and directions tried, indices up to this (-)
  std::size_t min_interfaces = 6;  ///< a band holds at least this many (-)
  double min_share = 0.1;      ///< a further band holds at least this part of the sliding interfaces' slip (-)
  std::size_t max_bands = 8;
};

/// The bands of `s` (its reference state is position - displacement), largest slip first. `lattice` and
/// s.crystal_orientation give the planes their indices. The search: for every lattice plane family with indices up
/// to max_index, the sliding interfaces crossing such a plane (branch at more than 15 degrees to it) are binned by
/// the position of their midpoints along its normal (bins half a neighbour distance wide); the family and bin holding
/// the most slip seed a band, which takes the crossing interfaces within half a neighbour distance of the bin's
/// centre; they are removed and the search repeats. Each band's plane is then fitted through its midpoints (least
/// squares) and named by the lattice plane nearest to it. Cost: O(families x interfaces), about 30 families.
std::vector<SlipBand> find_slip_bands(const GrainSnapshot& s, LatticeType lattice, const SlipBandOptions& o = {});

/// The lattice a snapshot's grain tiles (fcc for the rhombic dodecahedron, sc, bcc, hcp).
LatticeType snapshot_lattice(const GrainSnapshot& s);

/// The bands as the summary list "slip_bands" (a job's per snapshot, a snapshot file's own): `plane` "(h k l)" (HCP
/// "(h k i l)") and `plane_indices`, `angle_to_plane` (deg), `normal` (lab) and `offset` (m) of the fitted plane,
/// `slip` (m), `direction` "[u v w]" and `direction_indices`, `direction_angle` (deg), `dilation_angle` (deg),
/// `extent` (m), `interfaces`.
void write_slip_bands(SummaryWriter& w, const std::vector<SlipBand>& bands, LatticeType lattice);
/// Reads one element of that list back (a stored snapshot's), from `number(key)` and `triple(key, out)` lookups
/// the caller provides: the field names stay here.
template <class Number, class Triple>
SlipBand read_slip_band(const Number& number, const Triple& triple) {
  SlipBand b;
  triple("plane_indices", b.plane);
  triple("normal", b.normal);
  triple("direction_indices", b.direction);
  b.angle_to_plane = number("angle_to_plane"), b.offset = number("offset"), b.slip = number("slip");
  b.direction_angle = number("direction_angle"), b.dilation_angle = number("dilation_angle");
  b.extent = number("extent"), b.interfaces = std::uint32_t(number("interfaces"));
  return b;
}

/// "(h k l)" of a band's plane (HCP's four-index "(h k i l)"), for captions and tables.
std::string band_plane_text(const SlipBand& b, LatticeType lattice);

}  // namespace granulab
