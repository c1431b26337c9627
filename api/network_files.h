// A snapshot's contact network and grain shapes as the files OVITO and ParaView users expect (docs/api.md):
// force chains as VTK lines between touching grains' centres and as a LAMMPS local dump (one entry per grain pair in
// contact), and every grain as its polyhedron, posed, in a legacy VTK unstructured grid coloured by any per-grain field.
#pragma once

#include <string>

#include "engine/analysis/grain_snapshot.h"

namespace granulab::api {

/// Lines between the centres of the grain pairs in contact, with cell data `force` (the vector on the first grain,
/// N), `force_normal` (along the centre line, compressive positive), `force_tangential` (its magnitude across it),
/// `force_magnitude` and `sliding` (the interface's sliding distance, m; 0 for a pair that is no reference
/// interface); `force` and `force_normal` as VECTORS and SCALARS, the others in a FIELD block (api/legacy_vtk.h). No
/// lines for a snapshot stored before the network was kept.
std::string snapshot_contacts_vtk(const GrainSnapshot& s);
/// The same as a LAMMPS local dump ("ITEM: ENTRIES index grain_a grain_b fx fy fz force_normal force_tangential
/// sliding"), which OVITO reads as bonds' properties: grain_a and grain_b are the grain dump's ids (the grain's
/// id + 1).
std::string snapshot_contacts_dump(const GrainSnapshot& s);
/// The most spheres snapshot_spheres_dump writes (about 100 B each, built in memory: 100 MB; the reference crystal
/// has 841,536).
constexpr std::size_t kMaxDumpSpheres = 1000000;
/// Every sphere of every grain as a LAMMPS text dump ("id mol type x y z radius" and the grain's fields, d2min and
/// misorientation only when the snapshot has them: mol is the grain dump's id, the grain's id + 1), rebuilt from the
/// grains' poses and the clump the snapshot names (N_e, kappa). Throws std::invalid_argument when the snapshot
/// predates that (no N_e kept) or would have more than kMaxDumpSpheres.
std::string snapshot_spheres_dump(const GrainSnapshot& s);
/// Every grain as its polyhedron (the snapshot's grain shape and cubic cell, times the grain's scale), placed and
/// turned as the grain is: polygon cells of an UNSTRUCTURED_GRID, their cell data the grain's id (the active scalars) and fields (a FIELD
/// block).
std::string snapshot_meshes_vtk(const GrainSnapshot& s);

}  // namespace granulab::api
