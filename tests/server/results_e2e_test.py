#!/usr/bin/python3
"""Results end to end against a real granulabd (issue 11 §3, §4): a 3-job crystal sweep and a two-cube job run
through the daemon, and everything a user reads of them is checked: the live curve while a job runs, the
curve pictures (one job's, the sweep's overlay), the {111} section pictures of the snapshots with their
fields and slices, the snapshot exports (JSON, LAMMPS dump, VTK) and the tar archive of a job.

One daemon (--workers 1 --threads 1, a real SQLite file in a temporary folder) serves the whole class: the
jobs are submitted and watched once in setUpClass (about 20 s on 2 cores), the tests then read the results.

Standard library only. The daemon binary comes from $GRANULABD (set by CTest) or build/granulabd.
"""
import csv
import http.client
import io
import json
import math
import os
import shutil
import signal
import socket
import subprocess
import sys
import tarfile
import tempfile
import time
import unittest
import urllib.parse
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "clients", "python"))
from granulab_client import Client  # noqa: E402

DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
SVG = "{http://www.w3.org/2000/svg}"

# 6 x 12 x 3 = 216 grains, 72 in each {111} layer. A time step factor of 0.4 (instead of 0.2) makes the
# confinement about 0.5-1.5 s, and R = 5e-6 makes the compression 3-8 s on one thread (the fastest and the
# slowest machine seen; at 2e-5 the fastest finished it within one store of the live curve, which is every
# second): long enough for the live curve to be caught growing, short enough for three jobs in under a minute.
PRESSURES = [10000, 30000, 60000]
GRAINS_X, ROWS_Z, LAYERS_Y = 6, 12, 3
GRAINS = GRAINS_X * ROWS_Z * LAYERS_Y
PER_LAYER = GRAINS_X * ROWS_Z
CURVE_POINTS = 100
CRYSTAL_LABEL = "e2e crystal & <sweep>"  # escaped in the SVG, read back unescaped
SWEEP_LABEL = "e2e pressure sweep"
CRYSTAL = {"experiment": "crystal_compression", "label": CRYSTAL_LABEL,
           "grain": {"shape": "rhombic_dodecahedron", "edge_spheres": 4},
           "crystal": {"grains_x": GRAINS_X, "rows_z": ROWS_Z, "layers_y": LAYERS_Y},
           "loading": {"confining_pressure": 30000, "max_strain": 0.01, "rate_number": 5e-6},
           "run": {"time_step_factor": 0.4},
           "output": {"curve_points": CURVE_POINTS, "snapshot_strains": [0, 0.01]}}
FIELDS = ["penetration_ratio", "gamma_max", "equivalent_strain", "displacement"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def two_cube_spec():
    with open(os.path.join(ROOT, "examples", "two_cube_f03.json")) as f:
        spec = json.load(f)
    spec["grain"]["edge_spheres"] = 4
    spec["output"] = {"curve_points": 20}
    return spec


def series_of(root):
    """The curves drawn solid: the headline's series (the dashed ones are its closed forms and estimates)."""
    return [p for p in root.iter(SVG + "polyline") if p.get("class") == "series" and not p.get("stroke-dasharray")]


def references_of(root):
    """The dashed lines: closed forms, and a crystal's rigid-grain yield estimate."""
    return [p for p in root.iter(SVG + "polyline") if p.get("class") == "series" and p.get("stroke-dasharray")]


def points_of(element):
    return [tuple(float(v) for v in p.split(",")) for p in element.get("points").split()]


def title_of(root):
    """The plot's title: the first text element, bold, at the top."""
    first = next(root.iter(SVG + "text"))
    assert first.get("font-weight") == "bold", ET.tostring(first)
    return first.text or ""


def curve_rows(curve):
    return len(curve[curve["columns"][0]]) if curve.get("columns") else 0


class ResultsEndToEndTest(unittest.TestCase):
    proc = None
    dir = None

    # -- the daemon and HTTP -------------------------------------------------------------------------
    @classmethod
    def get(cls, path, **query):
        """(status, content type, body bytes) of a GET; no exception for 4xx."""
        if query:
            path += "?" + urllib.parse.urlencode(query)
        conn = http.client.HTTPConnection("127.0.0.1", cls.port, timeout=30)
        try:
            conn.request("GET", path)
            r = conn.getresponse()
            return r.status, r.getheader("Content-Type", ""), r.read()
        finally:
            conn.close()

    @classmethod
    def get_json(cls, path, **query):
        status, ctype, body = cls.get(path, **query)
        assert status == 200, (path, query, status, body[:300])
        assert ctype.startswith("application/json"), (path, ctype)
        return json.loads(body)

    def get_svg(self, path, **query):
        status, ctype, body = self.get(path, **query)
        self.assertEqual(status, 200, (path, query, body[:300]))
        self.assertTrue(ctype.startswith("image/svg+xml"), ctype)
        root = ET.fromstring(body)  # raises on anything that is not well-formed XML
        self.assertEqual(root.tag, SVG + "svg")
        return root

    def assert_error(self, status, field, path, query=None, code=None):
        """The error answer of a GET: its status, error.field (unless None) and error.code (unless None)."""
        got, ctype, body = self.get(path, **(query or {}))
        self.assertEqual(got, status, (path, query, body[:300]))
        self.assertTrue(ctype.startswith("application/json"), ctype)
        error = json.loads(body)["error"]
        if field is not None:
            self.assertEqual(error["field"], field, error)
        if code is not None:
            self.assertEqual(error["code"], code, error)
        self.assertTrue(error["message"])
        return error

    @classmethod
    def setUpClass(cls):
        cls.started = time.monotonic()
        cls.dir = tempfile.mkdtemp(prefix="granulab_results_")
        cls.db = os.path.join(cls.dir, "jobs.db")
        cls.port = free_port()
        cls.client = Client(f"http://127.0.0.1:{cls.port}", timeout=30)
        cls.proc = subprocess.Popen([DAEMON, "--port", str(cls.port), "--db", cls.db, "--workers", "1", "--threads", "1"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            cls.start_daemon_and_run_jobs()
        except BaseException:
            cls.tearDownClass()
            raise

    @classmethod
    def start_daemon_and_run_jobs(cls):
        deadline = time.time() + 20
        while True:
            try:
                cls.client.health()
                break
            except Exception:
                if time.time() > deadline or cls.proc.poll() is not None:
                    raise RuntimeError("granulabd did not start")
                time.sleep(0.05)
        assert os.path.getsize(cls.db) > 0, "no SQLite file"

        # The sweep, with the raw status of its answer; then a two-cube job queued behind it.
        body = json.dumps({"spec": CRYSTAL, "vary": {"loading.confining_pressure": PRESSURES}, "label": SWEEP_LABEL})
        conn = http.client.HTTPConnection("127.0.0.1", cls.port, timeout=30)
        conn.request("POST", "/v1/sweeps", body=body, headers={"Content-Type": "application/json"})
        r = conn.getresponse()
        cls.sweep_status, cls.sweep_answer = r.status, json.loads(r.read())
        conn.close()
        cls.sweep_id = cls.sweep_answer.get("id")
        cls.jobs = cls.sweep_answer.get("jobs", [])
        cls.two_cube = cls.client.submit(two_cube_spec())

        # Watch the first job while it runs: (rows, curve) for every curve read that happened while it was
        # running (status "running" read before and after it), and one curve.svg drawn mid-run.
        cls.live_reads = []
        cls.live_curve_svg = None
        first = cls.jobs[0] if cls.jobs else None
        deadline = time.time() + 120
        while first is not None and time.time() < deadline:
            before = cls.client.status(first)["status"]
            if before in ("succeeded", "failed", "cancelled"):
                break
            if before == "running":
                curve = cls.client.curve(first)
                svg = cls.get(f"/v1/jobs/{first}/curve.svg") if cls.live_curve_svg is None and curve_rows(curve) else None
                if cls.client.status(first)["status"] == "running":
                    cls.live_reads.append((curve_rows(curve), curve))
                    if svg is not None:
                        cls.live_curve_svg = svg
            time.sleep(0.1)
        cls.final = {}
        for job in cls.jobs + [cls.two_cube]:
            try:
                cls.final[job] = cls.client.wait(job, timeout=120, poll=0.2)
            except Exception as e:  # failed or cancelled: the tests report it
                cls.final[job] = {"status": "error", "error": str(e)}
        cls.run_seconds = time.monotonic() - cls.started

    @classmethod
    def tearDownClass(cls):
        if cls.proc and cls.proc.poll() is None:
            cls.proc.send_signal(signal.SIGTERM)
            cls.proc.wait(timeout=30)
        if cls.dir:
            shutil.rmtree(cls.dir, ignore_errors=True)
        rows = [n for n, _ in getattr(cls, "live_reads", [])]
        print(f"results e2e: jobs done {getattr(cls, 'run_seconds', 0):.1f} s after the start; {len(rows)} curve reads "
              f"while job 1 ran, rows seen: {sorted(set(rows))}", file=sys.stderr)

    def succeeded(self, job):
        self.assertEqual(self.final[job]["status"], "succeeded", self.final[job])

    def snapshot_json(self, job, k):
        return self.get_json(f"/v1/jobs/{job}/snapshots/{k}", format="json")

    # -- 1. the sweep ------------------------------------------------------------------------------------
    def test_sweep_creates_three_jobs_that_succeed(self):
        self.assertEqual(self.sweep_status, 201, self.sweep_answer)
        self.assertEqual(len(self.jobs), 3)
        self.assertEqual(len(set(self.jobs)), 3)
        for job, pressure in zip(self.jobs, PRESSURES):  # product order: one key, in the order given
            self.succeeded(job)
            st = self.client.status(job)
            self.assertEqual(st["sweep_id"], self.sweep_id)
            self.assertEqual(st["sweep_values"], {"loading.confining_pressure": pressure})
            self.assertEqual(st["spec"]["loading"]["confining_pressure"], pressure)
            self.assertEqual(st["spec"]["label"], CRYSTAL_LABEL)
            self.assertIn("first_yield", st["summary"])
        sweep = self.client.sweep(self.sweep_id)
        self.assertEqual(sweep["counts"], {"succeeded": 3})
        self.assertEqual([j["id"] for j in sweep["jobs"]], self.jobs)
        self.assertNotIn("sweep_id", self.client.status(self.two_cube))

    # -- 2. the live curve ------------------------------------------------------------------------------------
    def test_live_curve_grows_while_the_job_runs(self):
        rows = [n for n, _ in self.live_reads]
        self.assertGreaterEqual(len(rows), 2, "job 1 was not caught running twice")
        self.assertEqual(rows, sorted(rows), "the live curve lost rows")
        grew = [(a, b) for a, b in zip(rows, rows[1:]) if b > a and a > 0]
        self.assertTrue(grew, f"no growth between two reads while running (rows read: {rows})")
        self.succeeded(self.jobs[0])
        final = self.client.curve(self.jobs[0])
        total = curve_rows(final)
        self.assertEqual(total, CURVE_POINTS + 1)
        self.assertLess(max(rows), total, "the whole curve was there while running")
        # The rows read while running are the finished curve's first rows, value for value.
        n, live = max(self.live_reads, key=lambda r: r[0])
        self.assertEqual(live["columns"], final["columns"])
        for c in final["columns"]:
            self.assertEqual(live[c], final[c][:n], c)

    def test_curve_csv_has_the_json_rows(self):
        for job in self.jobs + [self.two_cube]:
            self.succeeded(job)
            curve = self.client.curve(job)
            text = self.client.curve_csv(job)
            table = list(csv.reader(io.StringIO(text)))
            self.assertEqual(table[0], curve["columns"])
            self.assertEqual(len(table) - 1, curve_rows(curve))
            self.assertGreater(len(table) - 1, 10)
            for i, row in enumerate(table[1:]):
                self.assertEqual(len(row), len(table[0]))
                for name, cell in zip(table[0], row):
                    self.assertEqual(float(cell), curve[name][i], (job, i, name))

    # -- 3. curve pictures ------------------------------------------------------------------------------------
    def test_sweep_curves_svg_overlays_one_series_per_job(self):
        for job in self.jobs:
            self.succeeded(job)
        root = self.get_svg(f"/v1/sweeps/{self.sweep_id}/curves.svg")
        self.assertEqual(title_of(root), SWEEP_LABEL)
        series = series_of(root)
        self.assertEqual(len(series), 3)
        for s, job in zip(series, self.jobs):
            self.assertEqual(len(points_of(s)), curve_rows(self.client.curve(job)))
            self.assertGreaterEqual(len(points_of(s)), 50)
            self.assertIsNone(s.get("stroke-dasharray"))
        self.assertEqual(len({s.get("stroke") for s in series}), 3, "the curves share a colour")
        legend = [g for g in root.iter(SVG + "g") if g.get("class") == "legend"]
        self.assertEqual(len(legend), 1)
        texts = [t.text for t in legend[0].iter(SVG + "text")]
        self.assertEqual(len(texts), 3)
        for text, series_element, pressure in zip(texts, series, PRESSURES):
            self.assertIn(str(pressure), text)
            self.assertEqual(series_element.get("data-label"), text)
            for other in set(PRESSURES) - {pressure}:
                self.assertNotIn(str(other), text)
        # In the crystal's natural units (p0) the axis says so; in SI (kPa) higher confinement is a higher
        # deviator: the curves are the jobs' own, not one curve drawn three times.
        self.assertIn("(p0)", "".join(root.itertext()))
        si = self.get_svg(f"/v1/sweeps/{self.sweep_id}/curves.svg", units="si")
        self.assertIn("(kPa)", "".join(si.itertext()))
        tops = [min(y for _, y in points_of(s)) for s in series_of(si)]  # SVG y grows downwards
        self.assertEqual(tops, sorted(tops, reverse=True), tops)

    def test_crystal_curve_svg_has_three_series_and_the_first_yield(self):
        for job, pressure in zip(self.jobs, PRESSURES):
            self.succeeded(job)
            root = self.get_svg(f"/v1/jobs/{job}/curve.svg")
            # A sweep's job is titled with the sweep's label and its own varied values.
            self.assertEqual(title_of(root), f"{SWEEP_LABEL} (loading.confining_pressure={pressure})")
            series = series_of(root)
            self.assertEqual([s.get("data-label") for s in series], ["deviator", "top platen", "bottom platen"])
            # Dashed beside them, the rigid-grain estimate of the first yield on a {111} plane (docs/model.md).
            self.assertEqual([s.get("data-label") for s in references_of(root)],
                             ["rigid-grain yield estimate, (1 -1 -1)"])
            rows = curve_rows(self.client.curve(job))
            for s in series:
                self.assertEqual(len(points_of(s)), rows)
            # The headline's key values, first yield and peak: circled and numbered on the deviator, their
            # words in the legend (never over the curves).
            # A peak the deviator never fell after (still rising at 1 %) is none: named with its reason, not marked.
            summary = self.client.status(job)["summary"]
            self.assertTrue(summary["first_yield"]["found"], summary["first_yield"])
            markers = [g for g in root.iter(SVG + "g") if g.get("class") == "marker"]
            self.assertEqual(len(markers), 2 if summary["peak"]["found"] else 1)
            self.assertEqual(["".join(m.itertext()) for m in markers], ["1", "2"][:len(markers)])
            label = markers[0].get("data-label")
            self.assertIn("first yield", label)
            ratio = summary["first_yield"]["deviator_over_p0"]
            self.assertIn(f"{ratio:.3g} p0", label)
            legend = "".join(next(g for g in root.iter(SVG + "g") if g.get("class") == "legend").itertext())
            self.assertIn(label, legend)
            if summary["peak"]["found"]:
                self.assertIn(markers[1].get("data-label"), legend)
                self.assertIn("peak", markers[1].get("data-label"))
            else:
                self.assertIn("peak:noneto", "".join(legend.split()))
            # The deviator in p0 (natural units, the default) and in kPa (SI): the same rows, scaled by p0 / 1000.
            si = self.get_svg(f"/v1/jobs/{job}/curve.svg", units="si")
            self.assertIn("stress (p0)", "".join(root.itertext()))
            self.assertIn("stress (kPa)", "".join(si.itertext()))
            self.assertEqual(len(points_of(series_of(si)[0])), rows)
            # One column instead of the headline's series: the chooser's ?y=.
            one = self.get_svg(f"/v1/jobs/{job}/curve.svg", y="lateral_stress")
            self.assertEqual([s.get("data-label") for s in series_of(one)], ["lateral_stress"])
            self.assertEqual(len(points_of(series_of(one)[0])), rows)
            self.assert_error(400, "y", f"/v1/jobs/{job}/curve.svg", {"y": "no_such_column"})
            self.assert_error(400, "units", f"/v1/jobs/{job}/curve.svg", {"units": "imperial"})

    def test_curve_svg_of_a_running_job_has_no_marker_yet(self):
        self.assertIsNotNone(self.live_curve_svg, "no curve.svg was drawn while job 1 ran")
        status, ctype, body = self.live_curve_svg
        self.assertEqual(status, 200)
        self.assertTrue(ctype.startswith("image/svg+xml"), ctype)
        root = ET.fromstring(body)
        self.assertEqual(title_of(root), f"{SWEEP_LABEL} (loading.confining_pressure={PRESSURES[0]}) (running)")
        self.assertEqual(len(series_of(root)), 3)
        self.assertGreater(len(points_of(series_of(root)[0])), 0)
        self.assertEqual([g for g in root.iter(SVG + "g") if g.get("class") == "marker"], [])

    def test_two_cube_curve_svg_has_the_dashed_eq1_lines(self):
        self.succeeded(self.two_cube)
        root = self.get_svg(f"/v1/jobs/{self.two_cube}/curve.svg")
        self.assertEqual(title_of(root), two_cube_spec()["label"])
        dashed, solid = references_of(root), series_of(root)
        self.assertEqual(len(dashed) + len(solid), 4)
        self.assertEqual([s.get("data-label") for s in solid], ["P", "T"])
        self.assertIn("force (P0)", "".join(root.itertext()))
        self.assertEqual(len(dashed), 2)
        self.assertTrue(all("eq. 1" in s.get("data-label") for s in dashed))
        self.assertIn("f = 0.3", dashed[1].get("data-label"))
        rows = curve_rows(self.client.curve(self.two_cube))
        self.assertGreaterEqual(rows, 20)
        for s in solid:
            self.assertEqual(len(points_of(s)), rows)
        for s in dashed:  # straight lines: two ends
            self.assertEqual(len(points_of(s)), 2)
        self.assertEqual([g for g in root.iter(SVG + "g") if g.get("class") == "marker"], [])

    # -- 4. snapshot pictures ------------------------------------------------------------------------------------
    def grain_polygons(self, job, k, **query):
        root = self.get_svg(f"/v1/jobs/{job}/snapshots/{k}.svg", **query)
        return [p for p in root.iter(SVG + "polygon") if p.get("class") == "grain"]

    def test_snapshot_svg_draws_the_middle_layer_for_every_field(self):
        job = self.jobs[1]
        self.succeeded(job)
        snapshots = self.client.snapshots(job)
        self.assertEqual([s["index"] for s in snapshots], [0, 1])
        for k in (0, 1):
            data = self.snapshot_json(job, k)["grains"]
            by_id = {gid: i for i, gid in enumerate(data["id"])}
            middle = None
            for field in FIELDS:
                polygons = self.grain_polygons(job, k, field=field)
                self.assertEqual(len(polygons), PER_LAYER, (k, field))
                ids = [int(p.get("data-id")) for p in polygons]
                self.assertEqual(len(set(ids)), PER_LAYER)
                self.assertTrue(set(ids) <= set(by_id))
                if middle is None:
                    middle = set(ids)
                self.assertEqual(set(ids), middle, "the fields draw different grains")
                for p in polygons:
                    points = points_of(p)
                    self.assertEqual(len(points), 6, (k, field, p.get("data-id")))  # a {111} section: a hexagon
                    self.assertEqual(len(set(points)), 6)
                    # The colour is the grain's own value (displacement shown in mm).
                    i = by_id[int(p.get("data-id"))]
                    if field == "displacement":
                        expected = 1e3 * math.sqrt(data["dx"][i] ** 2 + data["dy"][i] ** 2 + data["dz"][i] ** 2)
                    else:
                        expected = data[{"penetration_ratio": "penetration_ratio", "gamma_max": "gamma_max",
                                         "equivalent_strain": "equivalent_strain"}[field]][i]
                    self.assertAlmostEqual(float(p.get("data-value")), expected,
                                           delta=1e-5 * abs(expected) + 1e-12, msg=(k, field))
            default = {int(p.get("data-id")) for p in self.grain_polygons(job, k)}
            self.assertEqual(default, middle, "the default is not the middle layer")
            if k == 1:  # compressed: the grains have moved
                values = [float(p.get("data-value")) for p in self.grain_polygons(job, 1, field="displacement")]
                self.assertGreater(max(values), 0)

    def test_snapshot_zero_has_no_displacement(self):
        job = self.jobs[1]
        self.succeeded(job)
        values = [p.get("data-value") for p in self.grain_polygons(job, 0, field="displacement")]
        self.assertEqual(len(values), PER_LAYER)
        self.assertEqual([float(v) for v in values], [0.0] * PER_LAYER)

    def test_snapshot_svg_slices_partition_the_crystal(self):
        job = self.jobs[1]
        self.succeeded(job)
        all_ids = set(self.snapshot_json(job, 0)["grains"]["id"])
        self.assertEqual(len(all_ids), GRAINS)
        layers = []
        for layer in range(LAYERS_Y):
            polygons = self.grain_polygons(job, 0, slice=layer)
            self.assertEqual(len(polygons), PER_LAYER, layer)
            self.assertTrue(all(len(points_of(p)) == 6 for p in polygons))
            layers.append({int(p.get("data-id")) for p in polygons})
        self.assertEqual(set().union(*layers), all_ids)  # each grain in exactly one layer
        self.assertEqual(sum(len(s) for s in layers), GRAINS)
        self.assertEqual(layers[1], {int(p.get("data-id")) for p in self.grain_polygons(job, 0)})

    def test_snapshot_svg_rejects_bad_queries(self):
        job = self.jobs[1]
        self.succeeded(job)
        path = f"/v1/jobs/{job}/snapshots/0.svg"
        self.assert_error(400, "slice", path, {"slice": LAYERS_Y}, code="out_of_range")
        self.assert_error(400, "slice", path, {"slice": -1})
        self.assert_error(400, "slice", path, {"slice": "middle"})
        self.assert_error(400, "field", path, {"field": "bogus"}, code="invalid_value")
        self.assert_error(400, "colour", path, {"colour": "red"}, code="unknown_parameter")
        self.assert_error(404, None, f"/v1/jobs/{job}/snapshots/99.svg", code="not_found")
        self.assert_error(404, None, "/v1/jobs/987654/snapshots/0.svg")

    # -- 5. exports -------------------------------------------------------------------------------------------
    def test_snapshot_json_export(self):
        job = self.jobs[1]
        self.succeeded(job)
        for k in (0, 1):
            data = self.snapshot_json(job, k)
            self.assertEqual(len(data["grains"]["id"]), GRAINS)
            self.assertEqual(len(set(data["grains"]["id"])), GRAINS)
            self.assertEqual(data, self.client.snapshot(job, k))  # the default format
            self.assertGreater(len(data["interfaces"]["a"]), GRAINS)
        self.assertAlmostEqual(self.snapshot_json(job, 1)["strain"], 0.01, delta=1e-4)
        self.assert_error(404, None, f"/v1/jobs/{job}/snapshots/99", {"format": "json"})

    def test_snapshot_lammps_dump(self):
        job = self.jobs[1]
        self.succeeded(job)
        for k in (0, 1):
            data = self.snapshot_json(job, k)["grains"]
            status, ctype, body = self.get(f"/v1/jobs/{job}/snapshots/{k}", format="dump")
            self.assertEqual(status, 200)
            self.assertTrue(ctype.startswith("text/plain"), ctype)
            lines = body.decode().splitlines()
            at = lines.index("ITEM: NUMBER OF ATOMS")
            self.assertEqual(lines[at + 1], str(GRAINS))
            headers = [i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS ")]
            self.assertEqual(len(headers), 1)
            names = lines[headers[0]].split()[2:]
            self.assertIn("radius", names)
            self.assertEqual(names[:5], ["id", "type", "x", "y", "z"])  # as LAMMPS writes them
            atoms = lines[headers[0] + 1:]
            self.assertEqual(len(atoms), GRAINS)
            rows = [dict(zip(names, map(float, line.split()))) for line in atoms]
            for line in atoms:
                self.assertEqual(len(line.split()), len(names), line)
            radii = {r["radius"] for r in rows}
            self.assertEqual(len(radii), 1, radii)
            radius = radii.pop()
            self.assertGreater(radius, 0)
            # About half the grain spacing: an RD of cubic cell a = 0.01 m has neighbours a / sqrt 2 apart.
            self.assertAlmostEqual(radius, 0.01 / math.sqrt(2) / 2, delta=0.2 * 0.01 / math.sqrt(2) / 2)
            self.assertEqual([int(r["id"]) for r in rows], [i + 1 for i in data["id"]])  # from 1, as in LAMMPS
            self.assertEqual({r["type"] for r in rows}, {1})
            for r, x, z in zip(rows, data["x"], data["z"]):
                self.assertAlmostEqual(r["x"], x, delta=1e-8 * max(1.0, abs(x)))
                self.assertAlmostEqual(r["z"], z, delta=1e-8 * max(1.0, abs(z)))

    def test_snapshot_vtk_exports(self):
        job = self.jobs[1]
        self.succeeded(job)
        interfaces = len(self.snapshot_json(job, 1)["interfaces"]["a"])
        status, ctype, body = self.get(f"/v1/jobs/{job}/snapshots/1", format="vtk")
        self.assertEqual(status, 200)
        text = body.decode()
        self.assertTrue(text.startswith("# vtk DataFile"), text[:80])
        self.assertIn(f"\nPOINTS {GRAINS} ", text)
        self.assertIn("\nDATASET UNSTRUCTURED_GRID\n", text)
        self.assertIn(f"\nCELLS {GRAINS} {2 * GRAINS}\n", text)
        self.assertIn(f"\nCELL_TYPES {GRAINS}\n", text)
        self.assertIn(f"\nPOINT_DATA {GRAINS}\n", text)
        status, ctype, body = self.get(f"/v1/jobs/{job}/snapshots/1", format="vtk_interfaces")
        self.assertEqual(status, 200)
        lines = body.decode().splitlines()
        self.assertTrue(lines[0].startswith("# vtk DataFile"))
        self.assertIn(f"POINTS {GRAINS} double", lines)
        at = lines.index(f"CELLS {interfaces} {3 * interfaces}")
        for line in lines[at + 1:at + 1 + interfaces]:
            two, a, b = map(int, line.split())
            self.assertEqual(two, 2)
            self.assertTrue(0 <= a < GRAINS and 0 <= b < GRAINS and a != b, line)
        self.assertEqual(lines[at + 1 + interfaces], f"CELL_TYPES {interfaces}")
        self.assertEqual(set(lines[at + 2 + interfaces:at + 2 + 2 * interfaces]), {"3"})  # VTK_LINE
        self.assertEqual(lines[at + 2 + 2 * interfaces], f"CELL_DATA {interfaces}")

    def test_snapshot_export_rejects_an_unknown_format(self):
        job = self.jobs[1]
        self.assert_error(400, "format", f"/v1/jobs/{job}/snapshots/0", {"format": "xml"}, code="invalid_value")
        self.assert_error(400, "slice", f"/v1/jobs/{job}/snapshots/0", {"slice": 1}, code="unknown_parameter")

    # -- 6. the archive ---------------------------------------------------------------------------------------
    def test_archive_holds_the_whole_job(self):
        job = self.jobs[2]
        self.succeeded(job)
        status, ctype, body = self.get(f"/v1/jobs/{job}/archive")
        self.assertEqual(status, 200)
        self.assertEqual(ctype, "application/x-tar")
        with tarfile.open(fileobj=io.BytesIO(body)) as tar:
            members = {m.name: m for m in tar.getmembers()}
            read = lambda name: tar.extractfile(members[name]).read().decode()  # noqa: E731
            top = f"job_{job}/"
            expected = {top + name for name in ("spec.json", "summary.json", "curve.csv", "curve.svg")}
            snapshots = [s["index"] for s in self.client.snapshots(job)]
            self.assertEqual(snapshots, [0, 1])
            for k in snapshots:
                expected |= {f"{top}snapshots/snapshot_{k}{suffix}"
                             for suffix in (".json", ".dump", "_grains.vtk", "_interfaces.vtk", "_contacts.vtk", "_contacts.dump", "_meshes.vtk", "_dic.csv", "_dic.vtk")}
            self.assertEqual(set(members), expected)
            self.assertTrue(all(m.isfile() for m in members.values()))
            st = self.client.status(job)
            self.assertEqual(read(top + "curve.csv"), self.client.curve_csv(job))
            self.assertEqual(json.loads(read(top + "spec.json")), st["spec"])
            self.assertEqual(json.loads(read(top + "summary.json")), st["summary"])
            svg = ET.fromstring(read(top + "curve.svg"))
            self.assertEqual(len(series_of(svg)), 3)
            for k in snapshots:
                self.assertEqual(json.loads(read(f"{top}snapshots/snapshot_{k}.json")), self.snapshot_json(job, k))
                for suffix, fmt in ((".dump", "dump"), ("_grains.vtk", "vtk"), ("_interfaces.vtk", "vtk_interfaces"),
                                    ("_contacts.vtk", "contacts_vtk"), ("_contacts.dump", "contacts_dump"),
                                    ("_meshes.vtk", "mesh_vtk"), ("_dic.csv", "dic_csv"), ("_dic.vtk", "dic_vtk")):
                    status, _, body = self.get(f"/v1/jobs/{job}/snapshots/{k}", format=fmt)
                    self.assertEqual(status, 200)
                    self.assertEqual(read(f"{top}snapshots/snapshot_{k}{suffix}"), body.decode(), (k, fmt))
        self.assert_error(404, None, "/v1/jobs/987654/archive")


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main()
