// Grain snapshots as files: a compact JSON document (per-grain and per-interface arrays, what the
// server stores), a LAMMPS text dump (OVITO reads its columns, quaternion included), and legacy VTK
// polydata for ParaView: grains as points, interfaces as lines carrying their sliding distance.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "engine/analysis/grain_snapshot.h"

namespace granulab::api {

nlohmann::json snapshot_json(const GrainSnapshot& s);
std::string snapshot_lammps_dump(const GrainSnapshot& s);
std::string snapshot_grains_vtk(const GrainSnapshot& s);
std::string snapshot_interfaces_vtk(const GrainSnapshot& s);

}  // namespace granulab::api
