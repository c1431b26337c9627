// The contact network and grain shape files (api/network_files.h) on a hand-made snapshot of three cubes in a row:
//  - a contact's force splits into its part along the centre line (compressive positive) and across it, both in the
//    VTK lines and the LAMMPS local dump, with the interface's sliding;
//  - each grain is its cube, placed, turned and scaled as the grain is: every vertex at its pose;
//  - the network and the scales survive the JSON round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "api/network_files.h"
#include "api/snapshot_files.h"
#include "engine/geometry/polyhedron.h"

namespace granulab::api {
namespace {

constexpr double kA = 0.01;

GrainSnapshot three_cubes() {
  GrainSnapshot s;
  s.grain_shape = Shape::cube;
  s.grain_size = kA;
  for (int i = 0; i < 3; ++i) {
    s.id.push_back(GrainId(std::uint32_t(10 + i)));
    s.position.emplace_back(i * kA, 0, 0);
    s.displacement.push_back(Vec3::Zero());
    s.orientation.push_back(i == 2 ? Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ())) : Quat::Identity());
    s.penetration.push_back(0), s.penetration_ratio.push_back(1), s.gamma_max.push_back(0.1 * i);
    s.equivalent_strain.push_back(0);
  }
  s.scale = {1.0, 1.0, 0.5};
  s.interfaces = {{GrainId(10), GrainId(11)}, {GrainId(11), GrainId(12)}};
  s.sliding = {2e-5, 0};
  // Grain 10 is pushed away from 11 (along -x) and dragged along y.
  s.contacts = {{GrainId(10), GrainId(11)}};
  s.contact_force = {Vec3(-3.0, 4.0, 0.0)};
  return s;
}

TEST(NetworkFiles, AContactsForceSplitsAlongAndAcrossItsCentreLine) {
  const GrainSnapshot s = three_cubes();
  const std::string vtk = snapshot_contacts_vtk(s);
  EXPECT_NE(vtk.find("DATASET UNSTRUCTURED_GRID\n"), std::string::npos) << vtk;
  EXPECT_NE(vtk.find("CELLS 1 3\n2 0 1\nCELL_TYPES 1\n3\n"), std::string::npos) << vtk;  // one VTK_LINE
  EXPECT_NE(vtk.find("VECTORS force double\n-3 4 0\n"), std::string::npos);
  EXPECT_NE(vtk.find("SCALARS force_normal double 1\nLOOKUP_TABLE default\n3\n"), std::string::npos);
  // Beyond the first scalars, a FIELD block: what VTK's legacy readers read without being told to read all.
  EXPECT_NE(vtk.find("FIELD contact_fields 3\nforce_tangential 1 1 double\n4\nforce_magnitude 1 1 double\n5\n"
                     "sliding 1 1 double\n2e-05\n"),
            std::string::npos);
  EXPECT_EQ(vtk.find("SCALARS", vtk.find("SCALARS force_normal") + 1), std::string::npos);  // one SCALARS only
  // The grains' ids as the grain dump writes them: the grain's id + 1.
  const std::string dump = snapshot_contacts_dump(s);
  EXPECT_NE(dump.find("ITEM: NUMBER OF ENTRIES\n1\n"), std::string::npos);
  EXPECT_NE(dump.find("ITEM: ENTRIES index grain_a grain_b fx fy fz force_normal force_tangential sliding\n"
                      "1 11 12 -3 4 0 3 4 2e-05\n"),
            std::string::npos)
      << dump;
}

TEST(NetworkFiles, EachGrainIsItsPolyhedronPosedAndScaled) {
  const GrainSnapshot s = three_cubes();
  const std::string vtk = snapshot_meshes_vtk(s);
  // A cube: 6 faces of 4 vertices per grain.
  EXPECT_NE(vtk.find("POINTS 72 double\n"), std::string::npos);
  EXPECT_NE(vtk.find("CELLS 18 90\n"), std::string::npos);
  EXPECT_NE(vtk.find("CELL_TYPES 18\n9\n"), std::string::npos);  // VTK_QUAD
  std::istringstream in(vtk.substr(vtk.find("POINTS 72 double\n") + 17));
  for (int g = 0; g < 3; ++g)
    for (int v = 0; v < 24; ++v) {
      Vec3 x;
      in >> x.x() >> x.y() >> x.z();
      const Vec3 local = s.orientation[g].conjugate() * (x - s.position[g]);
      const double half = 0.5 * kA * s.scale[g];
      // Written with 9 significant digits of coordinates up to 0.025 m: 1e-10 m.
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::abs(local[k]), half, 1e-10) << g << " " << v;
    }
  // The grain's fields on its faces: gamma_max 0.2 on each of the third grain's six.
  const std::string gamma = vtk.substr(vtk.find("\ngamma_max 1 18 double\n"));
  std::istringstream values(gamma.substr(gamma.find("double\n") + 7));
  std::vector<double> v(18);
  for (double& x : v) values >> x;
  for (int f = 0; f < 6; ++f) EXPECT_DOUBLE_EQ(v[12 + f], 0.2);
}

// A truncated octahedron (BCC's grain): its 6 squares as quads, each of its 8 hexagons as 4 triangles (meshio drops
// the cell data of a file with VTK_POLYGON cells), which tile the hexagon: their areas add up to the grain's surface.
TEST(NetworkFiles, AHexagonalFaceIsWrittenAsTrianglesThatTileIt) {
  GrainSnapshot s = three_cubes();
  s.grain_shape = Shape::truncated_octahedron;
  s.scale = {1.0, 1.0, 1.0};
  const std::string vtk = snapshot_meshes_vtk(s);
  const std::size_t per_grain = 6 + 8 * 4;
  EXPECT_NE(vtk.find("CELLS " + std::to_string(3 * per_grain) + " " + std::to_string(3 * (6 * 5 + 32 * 4)) + "\n"),
            std::string::npos);
  EXPECT_NE(vtk.find("CELL_DATA " + std::to_string(3 * per_grain) + "\n"), std::string::npos);
  const std::size_t points = 3 * (6 * 4 + 8 * 6);
  std::istringstream in(vtk.substr(vtk.find("POINTS " + std::to_string(points) + " double\n")));
  std::string word;
  in >> word >> word >> word;
  std::vector<Vec3> p(points);
  for (Vec3& x : p) in >> x.x() >> x.y() >> x.z();
  std::size_t count = 0, size = 0;
  in >> word >> count >> size;
  ASSERT_EQ(word, "CELLS");
  double area = 0;  // of the first grain
  int triangles = 0, quads = 0;
  for (std::size_t c = 0; c < count; ++c) {
    std::size_t k = 0;
    in >> k;
    std::vector<std::size_t> v(k);
    for (std::size_t& i : v) in >> i;
    ASSERT_TRUE(k == 3 || k == 4);
    (k == 3 ? triangles : quads) += 1;
    if (c >= per_grain) continue;
    for (std::size_t j = 1; j + 1 < k; ++j) area += 0.5 * (p[v[j]] - p[v[0]]).cross(p[v[j + 1]] - p[v[0]]).norm();
  }
  EXPECT_EQ(triangles, 3 * 32);
  EXPECT_EQ(quads, 3 * 6);
  in >> word >> count;
  ASSERT_EQ(word, "CELL_TYPES");
  std::size_t type = 0, fives = 0, nines = 0;
  for (std::size_t c = 0; c < count; ++c) in >> type, fives += type == 5, nines += type == 9;
  EXPECT_EQ(fives, 3u * 32u);
  EXPECT_EQ(nines, 3u * 6u);
  // The polyhedron's own faces' areas (Newell's formula over each face's corners).
  const Polyhedron solid = Polyhedron::make(Shape::truncated_octahedron, kA);
  double surface = 0;
  for (const Face& f : solid.faces()) {
    Vec3 twice = Vec3::Zero();
    for (std::size_t j = 0; j < f.vertices.size(); ++j) twice += f.vertices[j].cross(f.vertices[(j + 1) % f.vertices.size()]);
    surface += 0.5 * twice.norm();
  }
  EXPECT_NEAR(area, surface, 1e-9 * surface);
}

TEST(NetworkFiles, TheSphereDumpHasEverySphereOfEveryGrainWithItsGrainsId) {
  GrainSnapshot s = three_cubes();
  EXPECT_THROW(snapshot_spheres_dump(s), std::invalid_argument);  // stored before N_e was kept
  s.edge_spheres = 3, s.sphere_overlap = 0.5;
  const std::string dump = snapshot_spheres_dump(s);
  std::istringstream in(dump);
  std::string line;
  std::size_t atoms = 0;
  for (int k = 0; k < 4 && std::getline(in, line); ++k)
    if (k == 3) atoms = std::stoul(line);
  EXPECT_EQ(atoms % 3, 0u);
  EXPECT_GT(atoms, 3u * 8u);  // at least the corners of each cube's clump
  while (std::getline(in, line) && line.rfind("ITEM: ATOMS", 0) != 0) {
  }
  // No d2min and no misorientation in this snapshot: no column for them (rather than "nan").
  EXPECT_EQ(line, "ITEM: ATOMS id mol type x y z radius penetration_ratio gamma_max equivalent_strain");
  for (std::size_t k = 0; k < atoms; ++k) {
    std::size_t id = 0, mol = 0, type = 0;
    Vec3 x;
    double radius = 0;
    in >> id >> mol >> type >> x.x() >> x.y() >> x.z() >> radius;
    std::getline(in, line);
    const std::size_t g = k / (atoms / 3);
    ASSERT_EQ(id, k + 1);
    ASSERT_EQ(mol, 11 + g);  // the grain dump's id: the grain's id + 1
    ASSERT_EQ(type, 1u);
    // Inside its grain's cube (scaled), its radius scaled with it.
    const Vec3 local = s.orientation[g].conjugate() * (x - s.position[g]);
    EXPECT_LE(local.cwiseAbs().maxCoeff(), 0.5 * kA * s.scale[g] + 1e-10);
    EXPECT_GT(radius, 0);
  }
}

TEST(NetworkFiles, TheNetworkAndScalesSurviveTheJsonRoundTrip) {
  const GrainSnapshot s = three_cubes();
  const GrainSnapshot back = snapshot_from_json(snapshot_json(s));
  ASSERT_EQ(back.contacts.size(), 1u);
  EXPECT_EQ(value(back.contacts[0].a), 10u);
  EXPECT_EQ(value(back.contacts[0].b), 11u);
  EXPECT_EQ(back.contact_force[0], Vec3(-3, 4, 0));
  EXPECT_EQ(back.scale, s.scale);
  GrainSnapshot clumps = s;
  clumps.edge_spheres = 4, clumps.sphere_overlap = 0.75;
  const GrainSnapshot again = snapshot_from_json(snapshot_json(clumps));
  EXPECT_EQ(again.edge_spheres, 4);
  EXPECT_DOUBLE_EQ(again.sphere_overlap, 0.75);
}

}  // namespace
}  // namespace granulab::api
