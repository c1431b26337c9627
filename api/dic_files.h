// A snapshot's DIC-like map (engine/analysis/dic_map.h) as files to lay beside an experiment's DIC field: CSV, one
// row per grid node, and a legacy VTK image (STRUCTURED_POINTS) that ParaView opens as a surface.
#pragma once

#include <optional>
#include <string>

#include "engine/analysis/dic_map.h"

namespace granulab::api {

/// The map's default grid step (m): half the snapshot's neighbour distance, a few nodes per grain.
double default_dic_step(const GrainSnapshot& s);
/// The map of snapshot `s` at `step` (m; nullopt: default_dic_step) with at most `max_nodes` nodes. Throws
/// std::invalid_argument naming `step` when it is not a positive number or gives too many nodes.
DicMap snapshot_dic_map(const GrainSnapshot& s, std::optional<double> step, std::size_t max_nodes);
/// Columns x, z (reference, m), ux, uy, uz (m), exx, ezz, exz, gamma_max (-); "nan" where the node is outside
/// the face (CSV readers take it as not a number: pandas, numpy, ParaView's CSV reader).
std::string dic_csv(const DicMap& m);
/// The same fields on the image's points: `measured` (1 inside the face, 0 not: the active scalars), the vector
/// `displacement`, and exx, ezz, exz, gamma_max in a FIELD block (api/legacy_vtk.h). A node outside the face has 0
/// in every field (VTK's legacy reader cannot read "nan"), as the file's title says.
std::string dic_vtk(const DicMap& m);

}  // namespace granulab::api
