#!/usr/bin/python3
"""A run's snapshot files as standard readers read them (issue 51, "files that readers misread"): `granulab run`
on a tiny crystal (16 grains, two snapshots, well under a second), then

- every legacy VTK file (grains, interfaces, contact network, polyhedra, the DIC-like map) through VTK 9's
  vtkDataSetReader twice: with its defaults (what a script gets: only the first SCALARS and VECTORS unless the arrays
  are in a FIELD block) and as ParaView reads (vtkPDataSetReader, every array): no error or warning, every array,
  its counts and values those of the snapshot's compact JSON (the DIC map's those of its CSV, nodes off the face
  0 with `measured` 0);
- the grain dump through ASE's `lammps-dump-text` reader (it needs a type column): every grain, at the JSON's
  positions, ids from 1 (the grain's id + 1, as LAMMPS counts); the contact dump's grain ids the same;
- the DIC CSV through VTK's CSV reader (ParaView's): every column numeric, "nan" read as not a number.

- every VTK file through meshio (Debian's python3-meshio): cells and arrays as the JSON has them.

Needs Debian's python3-vtk9, python3-ase and python3-meshio (`make deps` installs them); a test whose module is missing is skipped
and the program exits 77 (tests/skip_aware.py): ctest shows it as not run.
Run from the repository root:  /usr/bin/python3 tests/clients/snapshot_readers_test.py
(the CLI from $GRANULAB, set by CTest, or build/granulab).
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
import skip_aware  # noqa: E402

CLI = os.environ.get("GRANULAB") or os.path.join(ROOT, "build", "granulab")
SPEC = {"experiment": "crystal_compression", "grain": {"edge_spheres": 3},
        "crystal": {"grains_x": 2, "rows_z": 4, "layers_y": 2},
        "loading": {"confining_pressure": 30e3, "max_strain": 2e-4},
        "output": {"curve_points": 8, "snapshot_strains": [0.0, 2e-4]}}
GRAINS, SNAPSHOTS, RD_FACES = 16, 2, 12

try:
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
    from vtkmodules.vtkIOInfovis import vtkDelimitedTextReader
    from vtkmodules.vtkIOLegacy import vtkDataSetReader
    from vtkmodules.vtkIOParallel import vtkPDataSetReader
except ImportError:
    vtkDataSetReader = None
try:
    import ase.io
except ImportError:
    ase = None

try:
    import meshio
except ImportError:
    meshio = None

need_vtk = unittest.skipIf(vtkDataSetReader is None, "no VTK for Python (Debian's python3-vtk9)")
need_meshio = unittest.skipIf(meshio is None, "no meshio (Debian's python3-meshio)")
need_ase = unittest.skipIf(ase is None, "no ASE (Debian's python3-ase)")


def setUpModule():
    global OUT
    OUT = tempfile.mkdtemp(prefix="granulab_readers_")
    with open(os.path.join(OUT, "spec.json"), "w") as f:
        json.dump(SPEC, f)
    subprocess.run([CLI, "run", os.path.join(OUT, "spec.json"), "--out", os.path.join(OUT, "run"), "--threads", "1",
                    "--quiet"], check=True, timeout=120)


def tearDownModule():
    shutil.rmtree(OUT, ignore_errors=True)


def path(k, suffix):
    return os.path.join(OUT, "run", "snapshots", "snapshot_%d%s" % (k, suffix))


def snapshot(k):
    with open(path(k, ".json")) as f:
        return json.load(f)


def read_vtk(test, file_name, like_paraview):
    """The dataset and its point and cell arrays by name ({name: [tuple, ...]}), asserting that VTK said nothing."""
    messages = vtkStringOutputWindow()
    vtkOutputWindow.SetInstance(messages)
    reader = vtkPDataSetReader() if like_paraview else vtkDataSetReader()
    reader.SetFileName(file_name)
    reader.Update()
    test.assertEqual(messages.GetOutput().strip(), "", file_name)
    data = reader.GetOutput()
    arrays = {}
    for kind, attributes in (("point", data.GetPointData()), ("cell", data.GetCellData())):
        for i in range(attributes.GetNumberOfArrays()):
            a = attributes.GetArray(i)
            arrays[(kind, a.GetName())] = [a.GetTuple(j) for j in range(a.GetNumberOfTuples())]
    return data, arrays


def close(a, b, digits):
    """Equal to `digits` significant digits (the files write 6 or 9)."""
    return abs(a - b) <= 10 ** (1 - digits) * abs(b) + 1e-300


class SnapshotReadersTest(unittest.TestCase):
    def assert_close(self, got, want, digits, what):
        self.assertEqual(len(got), len(want), what)
        for i, (g, w) in enumerate(zip(got, want)):
            g, w = (g, w) if isinstance(w, (tuple, list)) else ((g,), (w,))
            self.assertEqual(len(g), len(w), what)
            for a, b in zip(g, w):
                self.assertTrue(close(a, b, digits), "%s[%d]: %r, not %r" % (what, i, a, b))

    def test_the_run_wrote_every_file(self):
        for k in range(SNAPSHOTS):
            for suffix in (".json", ".dump", "_grains.vtk", "_interfaces.vtk", "_contacts.vtk", "_contacts.dump",
                           "_meshes.vtk", "_dic.csv", "_dic.vtk"):
                self.assertTrue(os.path.isfile(path(k, suffix)), path(k, suffix))
            self.assertEqual(len(snapshot(k)["grains"]["id"]), GRAINS)

    @need_vtk
    def test_vtk_reads_every_array_of_the_grains(self):
        for k in range(SNAPSHOTS):
            g = snapshot(k)["grains"]
            for paraview in (False, True):
                data, arrays = read_vtk(self, path(k, "_grains.vtk"), paraview)
                self.assertEqual(data.GetNumberOfPoints(), GRAINS)
                self.assertEqual(data.GetNumberOfCells(), GRAINS)  # a vertex each
                points = [data.GetPoint(i) for i in range(GRAINS)]
                self.assert_close(points, list(zip(g["x"], g["y"], g["z"])), 9, "points")
                self.assertEqual(set(arrays), {("point", n) for n in (
                    "id", "displacement", "penetration", "penetration_ratio", "gamma_max", "equivalent_strain",
                    "d2min", "misorientation", "misorientation_axis", "quaternion_wxyz")})
                self.assertEqual([int(v[0]) for v in arrays[("point", "id")]], g["id"])
                self.assert_close(arrays[("point", "displacement")], list(zip(g["dx"], g["dy"], g["dz"])), 6, "u")
                for name in ("penetration", "penetration_ratio", "gamma_max", "equivalent_strain", "d2min",
                             "misorientation"):
                    self.assert_close([v[0] for v in arrays[("point", name)]], g[name], 6, name)
                axes = list(zip(g["misorientation_axis_x"], g["misorientation_axis_y"], g["misorientation_axis_z"]))
                self.assert_close(arrays[("point", "misorientation_axis")], axes, 6, "axis")
                self.assert_close(arrays[("point", "quaternion_wxyz")], list(zip(g["qw"], g["qx"], g["qy"], g["qz"])),
                                  9, "quaternion")

    @need_vtk
    def test_vtk_reads_the_interfaces_and_the_contact_network(self):
        for k in range(SNAPSHOTS):
            s = snapshot(k)
            index = {grain: i for i, grain in enumerate(s["grains"]["id"])}
            for paraview in (False, True):
                data, arrays = read_vtk(self, path(k, "_interfaces.vtk"), paraview)
                f = s["interfaces"]
                self.assertEqual(data.GetNumberOfCells(), len(f["a"]))
                self.assertGreater(len(f["a"]), GRAINS)
                for c, (a, b) in enumerate(zip(f["a"], f["b"])):
                    ids = data.GetCell(c).GetPointIds()
                    self.assertEqual((ids.GetId(0), ids.GetId(1)), (index[int(a)], index[int(b)]))
                self.assertEqual(set(arrays), {("cell", "sliding")})
                self.assert_close([v[0] for v in arrays[("cell", "sliding")]], f["sliding"], 6, "sliding")

                data, arrays = read_vtk(self, path(k, "_contacts.vtk"), paraview)
                c = s["contact_network"]
                self.assertEqual(data.GetNumberOfCells(), len(c["a"]))
                self.assertGreater(len(c["a"]), 0)
                self.assertEqual(set(arrays), {("cell", n) for n in (
                    "force", "force_normal", "force_tangential", "force_magnitude", "sliding")})
                self.assert_close(arrays[("cell", "force")], list(zip(c["fx"], c["fy"], c["fz"])), 6, "force")
                for (fn,), (ft,), (fm,) in zip(arrays[("cell", "force_normal")], arrays[("cell", "force_tangential")],
                                               arrays[("cell", "force_magnitude")]):
                    self.assertTrue(close(math.hypot(fn, ft), fm, 5), (fn, ft, fm))

    @need_vtk
    def test_vtk_reads_every_array_of_the_polyhedra(self):
        for k in range(SNAPSHOTS):
            g = snapshot(k)["grains"]
            for paraview in (False, True):
                data, arrays = read_vtk(self, path(k, "_meshes.vtk"), paraview)
                self.assertEqual(data.GetNumberOfCells(), GRAINS * RD_FACES)
                self.assertEqual(set(arrays), {("cell", n) for n in (
                    "id", "displacement", "penetration_ratio", "gamma_max", "equivalent_strain", "d2min",
                    "misorientation")})
                per_face = lambda values: [v for v in values for _ in range(RD_FACES)]  # noqa: E731
                self.assertEqual([int(v[0]) for v in arrays[("cell", "id")]], per_face(g["id"]))
                for name in ("penetration_ratio", "gamma_max", "equivalent_strain", "d2min", "misorientation"):
                    self.assert_close([v[0] for v in arrays[("cell", name)]], per_face(g[name]), 6, name)
                # The displacement vector, as in the grain file (one meaning per name).
                self.assert_close(arrays[("cell", "displacement")], per_face(list(zip(g["dx"], g["dy"], g["dz"]))),
                                  6, "u")

    @need_vtk
    def test_vtk_reads_every_array_of_the_dic_map(self):
        for k in range(SNAPSHOTS):
            with open(path(k, "_dic.csv")) as f:
                rows = [{key: float(v) for key, v in row.items()} for row in csv.DictReader(f)]
            s = snapshot(k)
            # The face: the layer of lowest reference y; the image lies at its mean reference y.
            g = s["grains"]
            y_ref = [y - dy for y, dy in zip(g["y"], g["dy"])]
            face = [y for y in y_ref if y < min(y_ref) + 0.5 * s["crystal"]["layer_spacing"]]
            for paraview in (False, True):
                data, arrays = read_vtk(self, path(k, "_dic.vtk"), paraview)
                self.assertEqual(data.GetNumberOfPoints(), len(rows))
                self.assertEqual(set(arrays), {("point", n) for n in (
                    "measured", "displacement", "exx", "ezz", "exz", "gamma_max")})
                measured = [int(v[0]) for v in arrays[("point", "measured")]]
                self.assertEqual(measured, [0 if math.isnan(r["exx"]) else 1 for r in rows])
                self.assertGreater(sum(measured), 0)
                for n, r in enumerate(rows):
                    x, y, z = data.GetPoint(n)
                    self.assertTrue(close(x, r["x"], 8) and close(z, r["z"], 8), (n, x, z, r))
                    self.assertAlmostEqual(y, sum(face) / len(face), delta=1e-9)
                    want = {name: (r[name] if measured[n] else 0.0) for name in r}
                    for name in ("exx", "ezz", "exz", "gamma_max"):
                        self.assertTrue(close(arrays[("point", name)][n][0], want[name], 9), (name, n))
                    self.assert_close([arrays[("point", "displacement")][n]], [(want["ux"], want["uy"], want["uz"])],
                                      9, "displacement")

    @need_vtk
    def test_vtks_csv_reader_reads_the_dic_csv_as_numbers(self):
        reader = vtkDelimitedTextReader()
        reader.SetFileName(path(1, "_dic.csv"))
        reader.SetHaveHeaders(True)
        reader.SetDetectNumericColumns(True)
        reader.Update()
        table = reader.GetOutput()
        with open(path(1, "_dic.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(table.GetNumberOfRows(), len(rows))
        self.assertTrue(any(r["exx"] == "nan" for r in rows))  # the hole-free crystal's map still has corners off it
        for c in range(table.GetNumberOfColumns()):
            column = table.GetColumn(c)
            self.assertTrue(column.IsNumeric(), column.GetName())
            for n, r in enumerate(rows):
                v, want = column.GetValue(n), float(r[column.GetName()])
                self.assertTrue(math.isnan(v) if math.isnan(want) else close(v, want, 9), (column.GetName(), n))

    @need_ase
    def test_ase_reads_every_grain_of_the_dump(self):
        for k in range(SNAPSHOTS):
            g = snapshot(k)["grains"]
            images = ase.io.read(path(k, ".dump"), format="lammps-dump-text", index=":")
            self.assertEqual(len(images), 1)
            atoms = images[0]
            self.assertEqual(len(atoms), GRAINS)
            self.assertEqual(set(atoms.get_atomic_numbers()), {1})  # type 1: one kind of grain
            # ASE orders the atoms by id: the JSON's order (ascending grain id).
            self.assert_close([tuple(p) for p in atoms.get_positions()], list(zip(g["x"], g["y"], g["z"])), 9,
                              "positions")
            with open(path(k, ".dump")) as f:
                lines = f.read().splitlines()
            header = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS "))
            names = lines[header].split()[2:]
            self.assertEqual(names[:2], ["id", "type"])
            rows = [dict(zip(names, map(float, line.split()))) for line in lines[header + 1:]]
            self.assertEqual([int(r["id"]) for r in rows], [i + 1 for i in g["id"]])
            for name in ("dx", "gamma_max", "d2min", "misorientation"):
                self.assert_close([r[name] for r in rows], g[name], 6, name)

    @need_meshio
    def test_meshio_reads_every_vtk_file_with_its_cells_and_arrays(self):
        """meshio refused the POLYDATA files; the unstructured grids read with every array, FIELD blocks included."""
        def data(mesh, kind):
            # meshio keeps point data as arrays, cell data as a list of arrays per cell block (one block here).
            d = mesh.point_data if kind == "point" else {n: v[0] for n, v in mesh.cell_data.items()}
            return {n: [tuple(x) if getattr(x, "shape", ()) else (float(x),) for x in v] for n, v in d.items()}

        for k in range(SNAPSHOTS):
            g = snapshot(k)["grains"]
            m = meshio.read(path(k, "_grains.vtk"))
            self.assertEqual(len(m.points), GRAINS)
            self.assertEqual([(b.type, len(b.data)) for b in m.cells], [("vertex", GRAINS)])
            arrays = data(m, "point")
            self.assertEqual([int(v[0]) for v in arrays["id"]], g["id"])
            self.assert_close(arrays["displacement"], list(zip(g["dx"], g["dy"], g["dz"])), 6, "u")
            for name in ("penetration_ratio", "gamma_max", "d2min", "misorientation"):
                self.assert_close([v[0] for v in arrays[name]], g[name], 6, name)
            self.assert_close(arrays["quaternion_wxyz"], list(zip(g["qw"], g["qx"], g["qy"], g["qz"])), 9, "q")

            f = snapshot(k)["interfaces"]
            m = meshio.read(path(k, "_interfaces.vtk"))
            self.assertEqual([(b.type, len(b.data)) for b in m.cells], [("line", len(f["a"]))])
            self.assert_close([v[0] for v in data(m, "cell")["sliding"]], f["sliding"], 6, "sliding")

            c = snapshot(k)["contact_network"]
            m = meshio.read(path(k, "_contacts.vtk"))
            self.assertEqual([(b.type, len(b.data)) for b in m.cells], [("line", len(c["a"]))])
            self.assert_close(data(m, "cell")["force"], list(zip(c["fx"], c["fy"], c["fz"])), 6, "force")

            m = meshio.read(path(k, "_meshes.vtk"))
            self.assertEqual(sum(len(b.data) for b in m.cells), GRAINS * RD_FACES)
            self.assertTrue(all(b.type.startswith("polygon") or b.type == "quad" for b in m.cells), m.cells)
            arrays = {n: [tuple(x) if getattr(x, "shape", ()) else (float(x),) for b in v for x in b]
                      for n, v in m.cell_data.items()}
            per_face = lambda values: [v for v in values for _ in range(RD_FACES)]  # noqa: E731
            self.assertEqual([int(v[0]) for v in arrays["id"]], per_face(g["id"]))
            self.assert_close(arrays["displacement"], per_face(list(zip(g["dx"], g["dy"], g["dz"]))), 6, "u")

            m = meshio.read(path(k, "_dic.vtk"))
            self.assertGreater(len(m.points), 0)
            self.assertIn("measured", m.point_data)

    def test_the_contact_dump_names_the_grain_dumps_ids(self):
        for k in range(SNAPSHOTS):
            c = snapshot(k)["contact_network"]
            with open(path(k, "_contacts.dump")) as f:
                lines = f.read().splitlines()
            at = lines.index("ITEM: NUMBER OF ENTRIES")
            self.assertEqual(int(lines[at + 1]), len(c["a"]))
            header = next(i for i, line in enumerate(lines) if line.startswith("ITEM: ENTRIES "))
            names = lines[header].split()[2:]
            rows = [dict(zip(names, map(float, line.split()))) for line in lines[header + 1:]]
            self.assertEqual([(int(r["grain_a"]), int(r["grain_b"])) for r in rows],
                             [(int(a) + 1, int(b) + 1) for a, b in zip(c["a"], c["b"])])
            self.assert_close([r["fx"] for r in rows], c["fx"], 6, "fx")


if __name__ == "__main__":
    skip_aware.main()
