#!/usr/bin/python3
"""Crystals of every lattice through a real granulabd (issue 26): SC along [1 1 0], BCC along [1 1 1] with its
lateral direction given, HCP along a1 in the four-index form [2 -1 -1 0] (compressions, with snapshots), and an
HCP confinement, a shear of cubes (crystal_shear, issue 27) and the cubes' elastic tensor (crystal_stiffness). Each is dry-run first (its estimate names its spheres), runs to `succeeded`, and what a user
reads of it holds: the normalised spec keeps the lattice and the axis, the grain shape follows the lattice, the
curve has its rows, the section picture of a snapshot draws the grains of one layer with the layer named by its
Miller indices, and a spec whose grain is not its lattice's is refused naming grain.shape. The dry runs carry the
rigid-grain yield estimate: Coulomb's (1 + f)/(1 - f) for the cubes along [1 1 0], f for the cubes sheared on a cube
face; the shear's summary has its peak, residual and dilation angle, and its curve picture draws the estimate.

One daemon (--workers 1 --threads 2, a real SQLite file in a temporary folder). About 20 s on 2 cores.
Standard library only. The daemon binary comes from $GRANULABD (set by CTest) or build/granulabd.
"""
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.request
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client, GranulabError  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
SVG = "{http://www.w3.org/2000/svg}"


def compression(lattice, axis, lateral=None, size=(3, 4, 5)):
    spec = {"experiment": "crystal_compression", "label": "%s along %s" % (lattice, axis),
            "grain": {"edge_spheres": 4},
            "crystal": {"lattice": lattice, "grains_x": size[0], "layers_y": size[1], "rows_z": size[2]},
            "loading": {"axis": axis, "confining_pressure": 30000, "max_strain": 0.002, "rate_number": 4e-5},
            "output": {"curve_points": 20, "snapshot_strains": [0, 0.002]}}
    if lateral:
        spec["loading"]["lateral"] = lateral
    return spec


# name: (spec, grain shape, the caption's layer planes)
CASES = {
    # x = [0 0 1] by default, y = [1 -1 0] / sqrt2
    "sc": (compression("sc", [1, 1, 0]), "cube", "(1 -1 0) layer"),
    # x = [1 -1 0], y = [1 1 1] x [1 -1 0] / sqrt6 = [1 1 -2] / sqrt6
    "bcc": (compression("bcc", [1, 1, 1], [1, -1, 0]), "truncated_octahedron", "(1 1 -2) layer"),
    # [2 -1 -1 0] = 3 a1 -> along a1; x = c by default (shorter than a1 + 2 a2), y = a1 x c: a prism plane
    "hcp": (compression("hcp", [2, -1, -1, 0]), "trapezo_rhombic_dodecahedron", "(0 1 -1 0) layer"),
}
SHEAR = {"experiment": "crystal_shear", "label": "cubes on (1 0 0) along [0 1 0]", "grain": {"edge_spheres": 4},
         "crystal": {"lattice": "sc", "grains_x": 4, "layers_y": 4, "rows_z": 4},
         "loading": {"plane": [1, 0, 0], "direction": [0, 1, 0], "confining_pressure": 30000,
                     "max_shear_strain": 0.01, "rate_number": 4e-5},
         "output": {"curve_points": 20, "snapshot_strains": [0.01]}}
STIFFNESS = {"experiment": "crystal_stiffness", "label": "cubes' elastic tensor", "grain": {"edge_spheres": 4},
             "crystal": {"lattice": "sc", "grains_x": 4, "layers_y": 4, "rows_z": 4},
             "loading": {"axis": [0, 0, 1], "lateral": [1, 0, 0], "confining_pressure": 30000}}
CONFINEMENT = {"experiment": "crystal_confinement", "grain": {"edge_spheres": 4},
               "crystal": {"lattice": "hcp", "grains_x": 3, "layers_y": 4, "rows_z": 5},
               "loading": {"confining_pressure": 30000}}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LatticeEndToEndTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.exists(DAEMON):
            raise unittest.SkipTest("no granulabd at " + DAEMON)
        cls.dir = tempfile.mkdtemp(prefix="granulab_lattice_")
        cls.port = free_port()
        cls.log = open(os.path.join(cls.dir, "daemon.log"), "w")
        cls.proc = subprocess.Popen([DAEMON, "--port", str(cls.port), "--db", os.path.join(cls.dir, "g.db"),
                                     "--workers", "1", "--threads", "2"], stdout=cls.log, stderr=subprocess.STDOUT)
        cls.client = Client("http://127.0.0.1:%d" % cls.port)
        for _ in range(200):
            try:
                cls.client.health()
                break
            except Exception:
                time.sleep(0.05)
        cls.estimates = {name: cls.client.dry_run(spec) for name, (spec, _, _) in CASES.items()}
        cls.estimates["shear"] = cls.client.dry_run(SHEAR)
        cls.jobs = {name: cls.client.submit(spec) for name, (spec, _, _) in CASES.items()}
        cls.jobs["confinement"] = cls.client.submit(CONFINEMENT)
        cls.jobs["shear"] = cls.client.submit(SHEAR)
        cls.jobs["stiffness"] = cls.client.submit(STIFFNESS)
        cls.final = {name: cls.client.wait(job, timeout=300) for name, job in cls.jobs.items()}

    @classmethod
    def tearDownClass(cls):
        if getattr(cls, "proc", None):
            cls.proc.terminate()
            cls.proc.wait(timeout=30)
            cls.log.close()
        shutil.rmtree(getattr(cls, "dir", ""), ignore_errors=True)

    def get(self, path):
        with urllib.request.urlopen("http://127.0.0.1:%d%s" % (self.port, path), timeout=30) as r:
            return r.read()

    def test_every_lattice_runs_to_its_end(self):
        for name, job in self.jobs.items():
            self.assertEqual(self.final[name]["status"], "succeeded", (name, self.final[name]))
        confinement = self.final["confinement"]["summary"]
        self.assertTrue(confinement["confinement"]["converged"], confinement["confinement"])

    def test_the_spec_keeps_its_lattice_and_axis_and_the_grain_follows(self):
        for name, (spec, shape, _) in CASES.items():
            job, summary = self.final[name], self.final[name]["summary"]
            self.assertEqual(job["spec"]["crystal"]["lattice"], name)
            self.assertEqual(job["spec"]["grain"]["shape"], shape)
            self.assertEqual(job["spec"]["loading"]["axis"], spec["loading"]["axis"])
            self.assertGreater(summary["grains"], 30)
            # The dry run counted the spheres the run had.
            self.assertEqual(self.estimates[name]["spheres"], summary["spheres"], name)

    def test_curves_rise_under_load(self):
        for name in CASES:
            curve = self.client.curve(self.jobs[name])
            deviator = curve["deviator"]
            self.assertGreaterEqual(len(deviator), 20, name)
            self.assertGreater(max(deviator), 0.2 * 30000, name)

    def test_sections_draw_the_grains_of_a_layer_and_name_its_planes(self):
        for name, (_, _, planes) in CASES.items():
            root = ET.fromstring(self.get("/v1/jobs/%d/snapshots/1.svg?field=displacement" % self.jobs[name]))
            grains = [p for p in root.iter(SVG + "polygon") if p.get("class") == "grain"]
            self.assertGreater(len(grains), 2, name)
            for p in grains:
                self.assertGreaterEqual(len(p.get("points").split()), 3, (name, p.get("data-id")))
            captions = " ".join(t.text or "" for t in root.iter(SVG + "text"))
            self.assertIn(planes, captions, name)

    def test_snapshots_carry_the_non_affine_residual_and_the_misorientation(self):
        for name in CASES:
            snap = self.client.snapshot(self.jobs[name], 1)
            grains = snap["grains"]
            n = len(grains["id"])
            for key in ("d2min", "misorientation", "misorientation_axis_x", "misorientation_axis_y",
                        "misorientation_axis_z"):
                self.assertEqual(len(grains[key]), n, (name, key))
            self.assertTrue(all(d >= 0 for d in grains["d2min"]), name)
            self.assertTrue(all(0 <= m <= 180 for m in grains["misorientation"]), name)
            self.assertGreater(max(grains["misorientation"]), 0, name)  # a compressed crystal's grains turn a little
            for i in range(n):
                axis = [grains["misorientation_axis_" + c][i] for c in "xyz"]
                length = sum(a * a for a in axis) ** 0.5
                self.assertTrue(abs(length - 1) < 1e-6 or (length == 0 and grains["misorientation"][i] == 0), (name, i))
            for field in ("d2min", "misorientation"):
                root = ET.fromstring(self.get("/v1/jobs/%d/snapshots/1.svg?field=%s" % (self.jobs[name], field)))
                captions = " ".join(t.text or "" for t in root.iter(SVG + "text"))
                self.assertIn("D²min" if field == "d2min" else "misorientation", captions, (name, field))
            dump = self.get("/v1/jobs/%d/snapshots/1?format=dump" % self.jobs[name]).decode()
            self.assertIn("d2min misorientation misorientation_axis_x", dump)

    def test_dry_runs_carry_the_rigid_grain_yield_estimate(self):
        f = 0.35  # the material's default friction
        cubes = self.estimates["sc"]["yield_estimate"]
        self.assertTrue(cubes["found"])
        self.assertAlmostEqual(cubes["axial_over_p0"], (1 + f) / (1 - f), places=9)
        self.assertEqual(len(cubes["plane"].strip("()").split()), 3)
        shear = self.estimates["shear"]["yield_estimate"]
        self.assertAlmostEqual(shear["shear_over_normal"], f, places=9)
        self.assertEqual((shear["plane"], shear["direction"]), ("(1 0 0)", "[0 1 0]"))
        self.assertAlmostEqual(shear["dilation_angle"], 0, places=6)
        self.assertEqual(shear["units"]["dilation_angle"], "deg")
        # BCC along [1 1 1]: no plane slides rigidly; the answer says so.
        self.assertFalse(self.estimates["bcc"]["yield_estimate"]["found"])
        self.assertIn("locked", self.estimates["bcc"]["yield_estimate"]["note"])

    def test_a_shear_reports_its_slip_law_and_draws_the_estimate(self):
        summary = self.final["shear"]["summary"]
        self.assertEqual(summary["layer_grains"], {"bottom": 16, "top": 16})
        self.assertGreater(summary["peak"]["shear_over_normal"], 0.2)
        self.assertIn("over_estimate", summary["peak"])
        self.assertIn("shear_over_normal", summary["residual"])
        self.assertIn("dilation_angle", summary)
        self.assertEqual(summary["yield_estimate"]["plane"], "(1 0 0)")
        curve = self.client.curve(self.jobs["shear"])
        self.assertGreaterEqual(len(curve["shear_over_normal"]), 20)
        self.assertAlmostEqual(curve["shear_strain"][-1], 0.01, delta=1e-4)
        svg = self.get("/v1/jobs/%d/curve.svg" % self.jobs["shear"]).decode()
        self.assertIn("rigid-grain estimate", svg)

    def test_a_stiffness_job_reports_its_tensors_in_pascals(self):
        summary = self.final["stiffness"]["summary"]
        for key in ("stiffness", "affine_stiffness", "affine_prediction"):
            c = summary[key]
            self.assertEqual([len(row) for row in c], [6] * 6, key)
            self.assertEqual(summary["units"][key + "[][]"], "Pa")
        # Cubes: C11 = N k_n / a, N the spheres of a face (docs/model.md, "Crystal stiffness").
        c11 = summary["spheres_per_face"] * summary["normal_stiffness"] / self.final["stiffness"]["spec"]["grain"]["size"]
        for key in ("stiffness", "affine_stiffness"):
            self.assertAlmostEqual(summary[key][0][0] / c11, 1, delta=0.01)
            self.assertAlmostEqual(summary[key][1][2] / c11, 0, delta=0.01)
        self.assertEqual(summary["states_not_converged"], 0)
        self.assertEqual([m["direction"] for m in summary["moduli"]], ["[1 0 0]", "[1 1 0]", "[1 1 1]"])
        curve = self.client.curve(self.jobs["stiffness"])
        self.assertEqual(len(curve["response"]), 38)  # two sets of a reference and 18 states
        self.assertEqual(sorted(set(curve["set"])), [0, 1])
        svg = self.get("/v1/jobs/%d/curve.svg" % self.jobs["stiffness"]).decode()
        self.assertIn("stress change", svg)

    def test_a_grain_that_is_not_the_lattices_is_refused_naming_the_field(self):
        spec = json.loads(json.dumps(CASES["sc"][0]))
        spec["grain"]["shape"] = "rhombic_dodecahedron"
        with self.assertRaises(GranulabError) as caught:
            self.client.submit(spec)
        self.assertEqual(caught.exception.status, 400)
        self.assertIn("grain.shape", str(caught.exception))
        self.assertIn("cube", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
