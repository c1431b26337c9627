// The DIC-like map of a snapshot's front face (engine/analysis/dic_map.h) drawn as the experiments' DIC fields are
// (the paper's Fig. 12): one square per grid node, coloured by a strain or displacement component, blank outside
// the face, the compression axis vertical, with a colour bar.
#pragma once

#include <optional>
#include <string>

#include "engine/analysis/dic_map.h"

namespace granulab::pictures {

enum class DicField { gamma_max, exx, ezz, exz, ux, uz };

/// "gamma_max", "exx", "ezz", "exz", "ux" or "uz"; nullopt for anything else.
std::optional<DicField> parse_dic_field(const std::string& name);
/// The SVG document; `strain` is the snapshot's, for the caption.
std::string dic_svg(const DicMap& m, DicField field, double strain, const std::string& title);

}  // namespace granulab::pictures
