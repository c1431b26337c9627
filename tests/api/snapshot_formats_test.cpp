// What standard readers need of a snapshot's files (issue 51), on a hand-made face of cubes with a hole in it:
//  - no file holds a "nan" or "inf" token (VTK's legacy reader stops at the first and still reports success), not
//    even the DIC image, whose nodes off the face carry 0 and measured 0; only the DIC CSV keeps "nan", which CSV
//    readers read;
//  - the LAMMPS dumps count grains from 1 and have a type column (ASE's reader refuses a dump without), and a field
//    the stored snapshot predates has no column rather than a column of "nan";
//  - in the VTK files every array after the first SCALARS and the first VECTORS is in a FIELD block, which VTK's
//    legacy readers read without being told to read all arrays.
// tests/clients/snapshot_readers_test.py reads a real run's files with VTK and ASE themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "api/dic_files.h"
#include "api/network_files.h"
#include "api/snapshot_files.h"

namespace granulab::api {
namespace {

constexpr double kA = 0.01;

// 6 x 6 cubes in the x-z plane at y = 0 (one layer: the front face), without the 2 x 2 in the middle, moved by a
// small uniform strain; no d2min and no misorientation (a snapshot stored before they were kept).
GrainSnapshot face_with_a_hole() {
  GrainSnapshot s;
  s.grain_shape = Shape::cube;
  s.grain_size = kA;
  s.step = 77;
  for (int k = 0; k < 6; ++k)
    for (int i = 0; i < 6; ++i) {
      if ((i == 2 || i == 3) && (k == 2 || k == 3)) continue;
      const Vec3 reference(i * kA, 0, k * kA), u(1e-3 * reference.x(), 0, -2e-3 * reference.z());
      s.id.push_back(GrainId(std::uint32_t(6 * k + i)));
      s.position.push_back(reference + u);
      s.displacement.push_back(u);
      s.orientation.push_back(Quat::Identity());
      s.penetration.push_back(1e-6), s.penetration_ratio.push_back(1), s.gamma_max.push_back(1.5e-3);
      s.equivalent_strain.push_back(2e-3);
    }
  for (std::size_t a = 0; a < s.id.size(); ++a)
    for (std::size_t b = a + 1; b < s.id.size(); ++b)
      if ((s.position[a] - s.position[b]).norm() < 1.1 * kA) {
        s.interfaces.push_back({s.id[a], s.id[b]});
        s.sliding.push_back(0);
        s.contacts.push_back({s.id[a], s.id[b]});
        s.contact_force.emplace_back(0.5, 0, 0);
      }
  return s;
}

std::vector<std::string> tokens(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string t; in >> t;) {
    std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    out.push_back(t);
  }
  return out;
}

bool not_a_number(const std::string& token) {
  for (const char* bad : {"nan", "-nan", "inf", "-inf", "+inf", "infinity", "-infinity"})
    if (token == bad) return true;
  return false;
}

TEST(SnapshotFormats, NoFileButTheDicCsvHoldsANanOrInfToken) {
  const GrainSnapshot s = face_with_a_hole();
  const std::vector<SnapshotFile> files = snapshot_files(3, s);
  ASSERT_EQ(files.size(), 9u);  // the DIC map's two files among them
  for (const SnapshotFile& f : files) {
    const std::vector<std::string> t = tokens(f.text);
    const bool csv = f.name.size() > 4 && f.name.substr(f.name.size() - 4) == ".csv";
    if (csv) continue;
    EXPECT_EQ(std::count_if(t.begin(), t.end(), not_a_number), 0) << f.name;
  }
  // The sphere dump is no file of a run (the server writes it on request): the same holds.
  GrainSnapshot clumps = s;
  clumps.edge_spheres = 2, clumps.sphere_overlap = 0.5;
  const std::vector<std::string> t = tokens(snapshot_spheres_dump(clumps));
  EXPECT_EQ(std::count_if(t.begin(), t.end(), not_a_number), 0);
}

TEST(SnapshotFormats, TheDicImageFillsNodesOffTheFaceWithZeroAndSaysSo) {
  const GrainSnapshot s = face_with_a_hole();
  const DicMap map = snapshot_dic_map(s, 0.5 * kA, 100000);
  const std::size_t nodes = std::size_t(map.nx) * std::size_t(map.nz);
  const std::size_t off =
      std::size_t(std::count_if(map.exx.begin(), map.exx.end(), [](double v) { return std::isnan(v); }));
  ASSERT_GT(off, 0u);  // the hole
  ASSERT_LT(off, nodes);
  const std::string vtk = dic_vtk(map);
  EXPECT_NE(vtk.find("nodes off the face have measured 0 and 0 in every field\n"), std::string::npos);
  std::istringstream in(vtk);
  std::string line;
  while (std::getline(in, line) && line != "SCALARS measured int 1") {}
  std::getline(in, line);  // LOOKUP_TABLE default
  std::vector<int> measured(nodes);
  for (int& m : measured) in >> m;
  in >> line;
  ASSERT_EQ(line, "VECTORS");
  std::getline(in, line);
  std::vector<Vec3> u(nodes);
  for (Vec3& x : u) in >> x.x() >> x.y() >> x.z();
  std::getline(in, line);
  std::getline(in, line);
  ASSERT_EQ(line, "FIELD strains 4");
  for (const auto& [name, field] : {std::pair<const char*, const std::vector<double>*>{"exx", &map.exx},
                                    {"ezz", &map.ezz},
                                    {"exz", &map.exz},
                                    {"gamma_max", &map.gamma_max}}) {
    std::getline(in, line);
    ASSERT_EQ(line, std::string(name) + " 1 " + std::to_string(nodes) + " double");
    for (std::size_t n = 0; n < nodes; ++n) {
      double v = -1;
      in >> v;
      EXPECT_EQ(measured[n], std::isnan(map.exx[n]) ? 0 : 1);
      if (std::isnan(map.exx[n])) EXPECT_EQ(v, 0) << name << " " << n;
      else EXPECT_NEAR(v, (*field)[n], 1e-8 * std::abs((*field)[n]) + 1e-15) << name << " " << n;
    }
    std::getline(in, line);
  }
  for (std::size_t n = 0; n < nodes; ++n)
    if (std::isnan(map.exx[n])) EXPECT_EQ(u[n], Vec3::Zero());
    else EXPECT_NEAR(u[n].z(), map.uz[n], 1e-8 * std::abs(map.uz[n]) + 1e-15);
  // The CSV keeps "nan" there: CSV readers (pandas, numpy, ParaView's) read it as not a number.
  EXPECT_NE(dic_csv(map).find(",nan,"), std::string::npos);
}

TEST(SnapshotFormats, TheGrainDumpCountsFromOneHasATypeAndNoColumnOfNan) {
  GrainSnapshot s = face_with_a_hole();
  std::string dump = snapshot_lammps_dump(s);
  const std::string header =
      "ITEM: ATOMS id type x y z radius dx dy dz quatw quati quatj quatk penetration "
      "penetration_ratio gamma_max equivalent_strain";
  EXPECT_NE(dump.find(header + "\n"), std::string::npos) << dump.substr(0, 400);
  std::istringstream in(dump.substr(dump.find(header) + header.size() + 1));
  for (std::size_t i = 0; i < s.id.size(); ++i) {
    std::string line;
    std::getline(in, line);
    std::istringstream row(line);
    unsigned long id = 0, type = 0;
    double x = 0;
    row >> id >> type >> x;
    EXPECT_EQ(id, value(s.id[i]) + 1ul);
    EXPECT_EQ(type, 1ul);
    EXPECT_NEAR(x, s.position[i].x(), 1e-12);
    EXPECT_EQ(tokens(line).size(), tokens(header).size() - 2) << line;  // "ITEM:" and "ATOMS"
  }
  // A snapshot that has them: their columns.
  s.d2min.assign(s.id.size(), 3e-12);
  s.misorientation.assign(s.id.size(), 0.25);
  s.misorientation_axis.assign(s.id.size(), Vec3::UnitZ());
  dump = snapshot_lammps_dump(s);
  EXPECT_NE(dump.find(header + " d2min misorientation misorientation_axis_x misorientation_axis_y "
                               "misorientation_axis_z\n"),
            std::string::npos);
  EXPECT_NE(dump.find(" 3e-12 0.25 0 0 1\n"), std::string::npos);
}

TEST(SnapshotFormats, EveryVtkArrayAfterTheFirstScalarsAndVectorsIsInAFieldBlock) {
  GrainSnapshot s = face_with_a_hole();
  s.d2min.assign(s.id.size(), 3e-12);
  s.misorientation.assign(s.id.size(), 0.25);
  s.misorientation_axis.assign(s.id.size(), Vec3::UnitZ());
  const std::size_t n = s.id.size();
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t c = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++c;
    return c;
  };
  const std::string grains = snapshot_grains_vtk(s);
  EXPECT_EQ(count(grains, "\nSCALARS "), 1u);
  EXPECT_EQ(count(grains, "\nVECTORS "), 1u);
  EXPECT_NE(grains.find("\nFIELD grain_fields 8\npenetration 1 " + std::to_string(n) + " double\n"), std::string::npos);
  for (const char* array : {"penetration_ratio 1 ", "gamma_max 1 ", "equivalent_strain 1 ", "d2min 1 ",
                            "misorientation 1 ", "misorientation_axis 3 ", "quaternion_wxyz 4 "})
    EXPECT_NE(grains.find("\n" + std::string(array) + std::to_string(n) + " double\n"), std::string::npos) << array;
  const std::string meshes = snapshot_meshes_vtk(s);
  EXPECT_EQ(count(meshes, "\nSCALARS "), 1u);
  EXPECT_NE(meshes.find("\nFIELD grain_fields 6\ndisplacement 3 " + std::to_string(6 * n) + " double\n"),
            std::string::npos);
  const std::string contacts = snapshot_contacts_vtk(s);
  EXPECT_EQ(count(contacts, "\nSCALARS "), 1u);
  EXPECT_EQ(count(contacts, "\nVECTORS "), 1u);
  EXPECT_NE(contacts.find("\nFIELD contact_fields 3\nforce_tangential 1 " + std::to_string(s.contacts.size())),
            std::string::npos);
  // A snapshot stored before the network was kept: no lines, no arrays, nothing a reader trips on.
  s.contacts.clear(), s.contact_force.clear();
  EXPECT_NE(snapshot_contacts_vtk(s).find("CELLS 0 0\nCELL_TYPES 0\nCELL_DATA 0\n"), std::string::npos);
}

}  // namespace
}  // namespace granulab::api
