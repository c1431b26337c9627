// Grain snapshots as files: a compact JSON document (per-grain and per-interface arrays, what the
// server stores), a LAMMPS text dump (OVITO reads its columns, quaternion included), and legacy VTK
// unstructured grids (ParaView, VTK, meshio): grains as vertices, interfaces as lines carrying their sliding distance.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/analysis/grain_snapshot.h"
#include "engine/crystal/lattice_type.h"

namespace granulab::api {

nlohmann::json snapshot_json(const GrainSnapshot& s);
/// A snapshot's slip bands (slip_bands.h) as JSON, as snapshots and job summaries carry them: `plane` "(h k l)"
/// (HCP "(h k i l)") and `plane_indices`, `angle_to_plane` (deg), `normal` (lab), `offset` (m), `slip` (m),
/// `direction` "[u v w]" and `direction_indices`, `direction_angle` (deg), `dilation_angle` (deg), `extent` (m),
/// `interfaces`.
nlohmann::json slip_bands_json(const std::vector<SlipBand>& bands, LatticeType lattice);
/// The inverse of snapshot_json (what the server stored back into a snapshot, for the other formats and
/// pictures); throws std::invalid_argument naming what is missing or inconsistent.
GrainSnapshot snapshot_from_json(const nlohmann::json& j);
/// A LAMMPS text dump of the grains: "id type x y z radius dx dy dz quatw quati quatj quatk penetration
/// penetration_ratio gamma_max equivalent_strain d2min misorientation misorientation_axis_x/_y/_z", ids from 1 (the
/// grain's id + 1, as LAMMPS counts), type 1; d2min and the misorientation only when the snapshot has them.
std::string snapshot_lammps_dump(const GrainSnapshot& s);
/// Grains as points: active scalars `id` (the grain's id, from 0 as in the JSON), vectors `displacement`, and a FIELD
/// block (api/legacy_vtk.h) of the per-grain measures and `quaternion_wxyz`.
std::string snapshot_grains_vtk(const GrainSnapshot& s);
std::string snapshot_interfaces_vtk(const GrainSnapshot& s);

/// One file of a snapshot: its name in a results folder (e.g. "snapshots/snapshot_2.dump") and text.
struct SnapshotFile {
  std::string name, text;
};
/// Snapshot k in every format, as `granulab run` writes them and the server's archive holds them:
/// snapshot_k.json, snapshot_k.dump, snapshot_k_grains.vtk, snapshot_k_interfaces.vtk, the contact network
/// snapshot_k_contacts.vtk and snapshot_k_contacts.dump, the grains' shapes snapshot_k_meshes.vtk (network_files.h),
/// and the front face's DIC-like
/// map at its default step, snapshot_k_dic.csv and snapshot_k_dic.vtk (api/dic_files.h).
std::vector<SnapshotFile> snapshot_files(std::size_t k, const GrainSnapshot& s);

}  // namespace granulab::api
