#!/usr/bin/python3
"""The bad-input suite (issue 10): a table of malformed requests against a real granulabd on loopback with a
real SQLite file, across every route and every spec field. The field cases are generated from
GET /v1/experiments, so a new experiment or field is covered without editing this file.

Every case asserts: no 5xx; a 4xx answers {"error": {"code", "message", "field"}}; a field-level error (a bad
value of a named spec field or query parameter) names it in `error.field` as a dotted path
("grain.edge_spheres", "crystal.knockout_regions[0].x", "limit"); and the daemon is still up (its process
after every case, GET /v1/health every 20 cases and at the end). A daemon that dies is counted as a crash,
restarted on the same file, and the suite goes on. One subTest per case, so one failure hides no other.
Good requests are cases too: the pictures are SVG that xml.etree parses, the archives tars that tarfile opens, and
a refused sweep leaves no job behind.

Run from the repository root:  /usr/bin/python3 tests/server/bad_input_test.py
Standard library only; the daemon binary comes from $GRANULABD (set by CTest) or build/granulabd, started with
`--workers 1 --threads 1` and no other option, so any build of the daemon can be tested.
"""
import gzip
import http.client
import io
import json
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import tarfile
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")

MAX_BODY = 1 << 20  # docs/api.md: bodies up to 1 MiB, chunked or not
HEALTH_EVERY = 20   # cases between two GET /v1/health
RAW_TIMEOUT = 2.0   # seconds a raw-socket case waits for its answer
HTTP_TIMEOUT = 10.0

# A short valid spec of each experiment (well under a second of work): the base every field case changes one
# field of, so that a spec wrongly accepted is a short job too (and is cancelled at once).
TINY = {
    "two_cube_sliding": {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 2},
                         "loading": {"rate_number": 0.1}, "output": {"curve_points": 4}},
    "crystal_compression": {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
                            "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1},
                            "loading": {"rate_number": 0.1}, "output": {"curve_points": 4}},
    "crystal_confinement": {"experiment": "crystal_confinement", "grain": {"edge_spheres": 2},
                            "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1}},
    "crystal_shear": {"experiment": "crystal_shear", "grain": {"edge_spheres": 2},
                      "crystal": {"lattice": "sc", "grains_x": 3, "rows_z": 5, "layers_y": 1},
                      "loading": {"rate_number": 0.1, "max_shear_strain": 0.001}, "output": {"curve_points": 4}},
    "crystal_stiffness": {"experiment": "crystal_stiffness", "grain": {"edge_spheres": 2},
                          # 6 a side: a knock-out region at the centre (a field case) still leaves interior grains
                          "crystal": {"lattice": "sc", "grains_x": 6, "rows_z": 6, "layers_y": 6},
                          "loading": {"ramp_transits": 1, "relax_checks": 1, "max_relax_transits": 10}},
    "crystal_tension": {"experiment": "crystal_tension", "grain": {"edge_spheres": 2},
                        # 5 layers: a knock-out region at the centre (a field case) still leaves free layers
                        "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 5, "layers_y": 1},
                        "loading": {"rate_number": 0.1, "max_strain": 0.001}, "output": {"curve_points": 4}},
}
REGION = {"x": 0, "z": 0, "radius": 1}  # a valid element of an array of objects (crystal.knockout_regions)
# Arrays whose elements hold exactly one of their fields (a loading program's segments): an element made
# of the field alone is valid, and this one is valid for the element cases.
ONE_OF = {"program": {"to_strain": 0.001}}
# ... where an experiment's elements are other fields (a shear's program moves to shear strains).
ONE_OF_OF = {("crystal_shear", "program"): {"to_shear_strain": 0.001}}


def valid_element(name, experiment=None):
    """A valid element of the array of objects `name` (its key, e.g. knockout_regions) of `experiment`."""
    return dict(ONE_OF_OF.get((experiment, name), ONE_OF.get(name, REGION)))


def tiny(experiment):
    return json.loads(json.dumps(TINY.get(experiment, {"experiment": experiment})))


# -- raw JSON tokens ----------------------------------------------------------------------------------------
# json.dumps cannot write NaN as a bare token on purpose, nor 1e400, nor an integer beyond 64 bits as text we
# choose: a marker string stands for the raw token and is replaced after dumping.
_RAW = re.compile(r'"\\u0000RAW:(.*?)\\u0000"')


def raw(token):
    return "\u0000RAW:" + token + "\u0000"


def dumps(doc):
    return _RAW.sub(lambda m: m.group(1), json.dumps(doc)).encode()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


# -- cases ----------------------------------------------------------------------------------------------------
class Case:
    """One request and what its answer must be.

    expect: a status, a tuple of statuses, or None (any status below 500).
    field:  the `error.field` a 4xx must carry (a string, or a tuple of acceptable names), or None.
    code:   the `error.code` a 4xx must carry (a string or a tuple), or None.
    pieces: for raw cases, the bytes sent on a socket, one piece after another (reading in between).
    """

    def __init__(self, name, method="GET", path="/", body=None, headers=None, expect=None, field=None, code=None,
                 pieces=None, check=None, no_answer_ok=False, continue_wait=0.0):
        self.name, self.method, self.path, self.body = name, method, path, body
        self.headers = headers if headers is not None else ({"Content-Type": "application/json"} if body is not None else {})
        self.expect, self.field, self.code, self.pieces = expect, field, code, pieces
        self.check, self.no_answer_ok, self.continue_wait = check, no_answer_ok, continue_wait


def post_spec(name, body, **kw):
    return Case(name, "POST", "/v1/jobs", body, **kw)


def post_sweep(name, body, query="", **kw):
    """POST /v1/sweeps with `body` (a document, dumped with dumps(), or bytes as they are)."""
    return Case(name, "POST", "/v1/sweeps" + query, body if isinstance(body, bytes) else dumps(body), **kw)


# -- checks of good answers (Case.check) ------------------------------------------------------------------------
def content_type(*types):
    """The answer's Content-Type is one of `types` (parameters such as charset aside)."""
    def check(test, status, headers, body, interim):
        got = headers.get("content-type", "")
        test.assertIn(got.split(";")[0].strip(), types, f"Content-Type {got!r}")
    return check


def both(*checks):
    def check(test, status, headers, body, interim):
        for c in checks:
            c(test, status, headers, body, interim)
    return check


def svg_parses(test, status, headers, body, interim):
    """A 200 is an SVG document xml.etree parses (a label with < & or control characters must not break it)."""
    if status != 200:
        return
    test.assertEqual(headers.get("content-type", "").split(";")[0], "image/svg+xml", headers.get("content-type"))
    try:
        root = ET.fromstring(body)
    except ET.ParseError as e:
        test.fail(f"the SVG does not parse: {e}: {body[:200]!r}")
    test.assertTrue(root.tag.endswith("svg"), root.tag)


def tar_holds(job, required, forbidden=()):
    """A 200 is a tar (application/x-tar) tarfile opens, every member under job_<id>/, holding `required`
    (names under that folder) and none of `forbidden`; every .svg in it parses and every .json loads."""
    def check(test, status, headers, body, interim):
        if status != 200:
            return
        got = headers.get("content-type", "")
        test.assertEqual(got.split(";")[0], "application/x-tar", got)
        try:
            tar = tarfile.open(fileobj=io.BytesIO(body))
            members = tar.getmembers()
        except tarfile.TarError as e:
            test.fail(f"tarfile cannot open the archive: {e}")
        names = [m.name for m in members]
        for name in names:
            test.assertTrue(name.startswith(f"job_{job}/") and ".." not in name.split("/"), f"member {name!r}")
        for name in required:
            test.assertIn(f"job_{job}/{name}", names, f"{name} missing from the archive: {names}")
        for name in forbidden:
            test.assertNotIn(f"job_{job}/{name}", names)
        for m in members:
            test.assertTrue(m.isfile(), m.name)
            data = tar.extractfile(m).read()
            try:
                if m.name.endswith(".svg"):
                    ET.fromstring(data)
                elif m.name.endswith(".json"):
                    json.loads(data)
            except (ET.ParseError, ValueError) as e:
                test.fail(f"{m.name} in the archive does not parse: {e}")
    return check


def json_holds(**expected):
    """A 200 is a JSON object with these values (a callable value is a predicate of the value)."""
    def check(test, status, headers, body, interim):
        if status // 100 != 2:
            return
        answer = json.loads(body)
        for key, want in expected.items():
            test.assertIn(key, answer, f"no {key!r} in {body[:200]!r}")
            if callable(want):
                test.assertTrue(want(answer[key]), f"{key} = {answer[key]!r}")
            else:
                test.assertEqual(answer[key], want, key)
    return check


def field_starts(prefix):
    """A 4xx whose error.field starts with `prefix` (and goes on after it): 'vary.' or 'spec.'."""
    def check(test, status, headers, body, interim):
        if 400 <= status < 500:
            field = json.loads(body)["error"]["field"]
            test.assertTrue(field.startswith(prefix) and len(field) > len(prefix),
                            f"error.field {field!r} does not start with {prefix!r}: {body[:300]!r}")
    return check


def nothing_made(marker):
    """After a refused sweep, no sweep and no job labelled with `marker` exists: a sweep is all or nothing."""
    def check(test, status, headers, body, interim):
        for path, key in (("/v1/sweeps?limit=1000", "sweeps"), ("/v1/jobs?limit=1000", "jobs")):
            got, _, listing = test.http("GET", path)
            test.assertEqual(got, 200, listing[:200])
            made = [x["id"] for x in json.loads(listing)[key] if marker in x.get("label", "")]
            test.assertEqual(made, [], f"the refused sweep left {key} behind: {made}")
    return check


def sweep_cases():
    """POST /v1/sweeps bodies: the envelope {spec, vary, mode, label}, the dotted keys of vary and their lists,
    the base spec. docs/api.md: a 400 names `vary.<key>` (or `spec.<field>` for the base spec), and nothing is
    created unless every point is valid."""
    two, crystal = tiny("two_cube_sliding"), tiny("crystal_compression")
    vary = {"loading.rate_number": [0.05, 0.1]}
    ok = {"spec": two, "vary": vary}
    deep = lambda n: raw("[" * n + "]" * n)
    S = post_sweep
    c = [
        # Not a JSON object.
        S("sweep: empty body", b"", expect=400, code="invalid_json"),
        S("sweep: not JSON", b"spec=1&vary=2", expect=400, code="invalid_json"),
        S("sweep: truncated", dumps(ok)[:-1], expect=400, code="invalid_json"),
        S("sweep: trailing garbage", dumps(ok) + b" {}", expect=400, code="invalid_json"),
        S("sweep: invalid UTF-8 in the label", dumps(dict(ok, label="@")).replace(b"@", b"\xff"), expect=400,
          code="invalid_json"),
        S("sweep: invalid UTF-8 in a vary key", dumps(ok).replace(b"loading.rate_number", b"loading.rate\xc3("),
          expect=400, code="invalid_json"),
        S("sweep: NaN token in a list", {"spec": two, "vary": {"loading.rate_number": [raw("NaN")]}}, expect=400,
          code="invalid_json"),
        S("sweep: top level null", b"null", expect=400, field=""),
        S("sweep: top level number", b"7", expect=400, field=""),
        S("sweep: top level string", b'"sweep"', expect=400, field=""),
        S("sweep: top level array", dumps([ok]), expect=400, field=""),
        # The envelope's keys.
        S("sweep: empty object", {}, expect=400, field=("spec", "vary")),
        S("sweep: unknown key", dict(ok, bogus=1), expect=400, field="bogus", code="unknown_field"),
        S("sweep: key in capitals", {"Spec": two, "vary": vary}, expect=400, field="Spec", code="unknown_field"),
        S("sweep: spec given twice", dumps(ok)[:-1] + b', "spec": ' + dumps(two) + b"}", expect=400, field="spec",
          code="duplicate_field"),
        S("sweep: vary given twice", dumps(ok)[:-1] + b', "vary": ' + dumps(vary) + b"}", expect=400, field="vary",
          code="duplicate_field"),
        S("sweep: a vary key given twice", dumps({"spec": two, "vary": {"label": ["a"]}})[:-2]
          + b', "label": ["b"]}}', expect=400, field="vary.label", code="duplicate_field"),
        S("sweep: label given twice", dumps(dict(ok, label="a"))[:-1] + b', "label": "b"}', expect=400, field="label",
          code="duplicate_field"),
        # spec: required (docs/openapi.json SweepRequest), an object, and valid where vary does not set it.
        # (A sweep without "spec" used to run the default, full-size experiment.)
        S("sweep: missing spec", {"vary": {"label": ["missing spec"]}}, expect=400, field="spec"),
        S("sweep: spec null", {"spec": None, "vary": vary}, expect=400, field="spec"),
        S("sweep: spec a list", {"spec": [two], "vary": vary}, expect=400, field="spec"),
        S("sweep: spec a string", {"spec": "two_cube_sliding", "vary": vary}, expect=400, field="spec"),
        S("sweep: spec with an unknown key", dict(ok, spec=dict(two, bogus=1)), expect=400, field="spec.bogus",
          code="unknown_field"),
        S("sweep: spec with an unknown experiment", dict(ok, spec={"experiment": "nope"}), expect=400,
          field="spec.experiment"),
        S("sweep: spec with a bad field", dict(ok, spec=set_path(tiny("two_cube_sliding"), "grain.edge_spheres", 1)),
          expect=400, field="spec.grain.edge_spheres"),
        S("sweep: spec with a field of the wrong type", dict(ok, spec=set_path(tiny("two_cube_sliding"), "grain.size",
                                                                              "big")),
          expect=400, field="spec.grain.size"),
        S("sweep: spec with 1e400", dict(ok, spec=set_path(tiny("two_cube_sliding"), "grain.size", raw("1e400"))),
          expect=400, field="spec.grain.size", code="out_of_range"),
        S("sweep: spec with a section of the wrong type", dict(ok, spec=dict(two, grain=5)), expect=400,
          field="spec.grain", code="wrong_type"),
        S("sweep: spec with a nested label", dict(ok, spec=dict(two, label=deep(10))), expect=400, field="spec.label"),
        S("sweep: spec with a bad field that vary sets", {"spec": set_path(tiny("two_cube_sliding"),
                                                                           "grain.edge_spheres", 1),
                                                          "vary": {"grain.edge_spheres": [2]}}, expect=201),
        # vary: an object of dotted keys, each a non-empty list.
        S("sweep: missing vary", {"spec": two}, expect=400, field="vary"),
        S("sweep: vary null", dict(ok, vary=None), expect=400, field="vary"),
        S("sweep: vary empty", dict(ok, vary={}), expect=400, field="vary"),
        S("sweep: vary a list", dict(ok, vary=[vary]), expect=400, field="vary"),
        S("sweep: vary a string", dict(ok, vary="loading.rate_number=0.05,0.1"), expect=400, field="vary"),
        S("sweep: vary a number", dict(ok, vary=1), expect=400, field="vary"),
        S("sweep: a vary value is a number", dict(ok, vary={"loading.rate_number": 0.05}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: a vary value is a string", dict(ok, vary={"label": "a"}), expect=400, field="vary.label"),
        S("sweep: a vary value is null", dict(ok, vary={"loading.rate_number": None}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: a vary value is an object", dict(ok, vary={"grain": {"edge_spheres": [2, 3]}}), expect=400,
          field="vary.grain"),
        S("sweep: an empty list", dict(ok, vary={"loading.rate_number": []}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: an empty list after a good one", dict(ok, vary={"label": ["a"], "loading.rate_number": []}),
          expect=400, field="vary.loading.rate_number"),
        S("sweep: vary the experiment", dict(ok, vary={"experiment": ["two_cube_sliding"]}), expect=400,
          field="vary.experiment"),
        # Dotted keys the spec does not have: the error names the key of vary.
        S("sweep: unknown top-level key", dict(ok, vary={"bogus": [1]}), expect=400, field="vary.bogus",
          code="unknown_field"),
        S("sweep: unknown key in a section", dict(ok, vary={"grain.bogus": [1]}), expect=400, field="vary.grain.bogus",
          code="unknown_field"),
        S("sweep: key below a number", dict(ok, vary={"grain.edge_spheres.x": [2]}), expect=400,
          field="vary.grain.edge_spheres.x"),
        S("sweep: key empty", dict(ok, vary={"": [1]}), expect=400, check=field_starts("vary")),
        # When the spec refuses a key above the varied one (a section or key vary creates, "bogus" of "bogus.x"),
        # the error names the varied key, not the base spec (it used to say "spec.bogus", "the base spec: ...").
        S("sweep: unknown section", dict(ok, vary={"bogus.x": [1]}), expect=400, field="vary.bogus.x",
          check=field_starts("vary.")),
        S("sweep: unknown key under a section", dict(ok, vary={"loading.bogus.x": [1]}), expect=400,
          field="vary.loading.bogus.x", check=field_starts("vary.")),
        S("sweep: a field of another experiment", dict(ok, vary={"crystal.grains_x": [2]}), expect=400,
          field="vary.crystal.grains_x", check=field_starts("vary.")),
        S("sweep: key with an array index", {"spec": crystal, "vary": {"crystal.knockout_regions[0].x": [0]}},
          expect=400, check=field_starts("vary.")),
        S("sweep: key with an empty part", dict(ok, vary={"grain..size": [0.01]}), expect=400,
          check=field_starts("vary.")),
        S("sweep: key a dot", dict(ok, vary={".": [1]}), expect=400, check=field_starts("vary.")),
        S("sweep: vary key in capitals", dict(ok, vary={"LOADING.RATE_NUMBER": [0.1]}), expect=400,
          check=field_starts("vary.")),
        # A bad value in a list: the key named, nothing created even when earlier points are good.
        S("sweep: value above the maximum", dict(ok, vary={"loading.rate_number": [0.05, 0.2]}), expect=400,
          field="vary.loading.rate_number", code="out_of_range"),
        S("sweep: value of the wrong type", dict(ok, vary={"loading.rate_number": [0.05, "fast"]}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: value a bool", dict(ok, vary={"grain.edge_spheres": [True]}), expect=400,
          field="vary.grain.edge_spheres"),
        S("sweep: value a fraction of an integer", dict(ok, vary={"grain.edge_spheres": [2, 2.5]}), expect=400,
          field="vary.grain.edge_spheres"),
        S("sweep: value a list", dict(ok, vary={"loading.rate_number": [[0.05]]}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: value an object", dict(ok, vary={"loading.rate_number": [{}]}), expect=400,
          field="vary.loading.rate_number"),
        S("sweep: value 1e400", dict(ok, vary={"loading.rate_number": [raw("1e400")]}), expect=400,
          code="out_of_range", check=field_starts("vary.")),
        S("sweep: value an unknown choice", dict(ok, vary={"grain.shape": ["sphere"]}), expect=400,
          field="vary.grain.shape"),
        S("sweep: value a bad section", dict(ok, vary={"grain": [{"bogus": 1}]}), expect=400, field="vary.grain"),
        S("sweep: label value a number", dict(ok, vary={"label": [1]}), expect=400, field="vary.label"),
        S("sweep: label value too long", dict(ok, vary={"label": ["x" * 201]}), expect=400, field="vary.label"),
        S("sweep: bad value in the last point only", {"spec": two, "label": "atomic-sweep-marker-1",
                                                      "vary": {"grain.edge_spheres": [2, 3, 41]}},
          expect=400, field="vary.grain.edge_spheres", check=nothing_made("atomic-sweep-marker-1")),
        S("sweep: bad value in the second list", {"spec": two, "label": "atomic-sweep-marker-2",
                                                  "vary": {"label": ["a", "b"], "loading.rate_number": [0.1, -1]}},
          expect=400, field="vary.loading.rate_number", check=nothing_made("atomic-sweep-marker-2")),
        # Over the per-job budget: docs/api.md, every point budgeted before any job exists.
        S("sweep: a point over budget", {"spec": set_path(set_path(tiny("crystal_compression"), "crystal",
                                                                   {"grains_x": 2, "rows_z": 18, "layers_y": 6}),
                                                          "loading.rate_number", 1e-8),
                                         "label": "atomic-sweep-marker-3", "vary": {"crystal.grains_x": [2, 20]}},
          expect=400, code="over_budget", check=nothing_made("atomic-sweep-marker-3")),
        # A value of vary that makes a whole section invalid (100 x 400 x 100 grains of N_e = 4, over the 5e7-sphere
        # limit the spec itself checks) is the varied key's fault: the base alone (2 x 400 x 100) is valid.
        S("sweep: a point with too many spheres", {"spec": set_path(set_path(set_path(tiny("crystal_compression"),
                                                                                     "crystal.rows_z", 400),
                                                                            "crystal.layers_y", 100),
                                                                   "grain.edge_spheres", 4),
                                                  "label": "atomic-sweep-marker-4",
                                                  "vary": {"crystal.grains_x": [2, 100]}},
          expect=400, field="vary.crystal.grains_x", check=nothing_made("atomic-sweep-marker-4")),
        # mode.
        S("sweep: mode unknown", dict(ok, mode="cartesian"), expect=400, field="mode"),
        S("sweep: mode empty", dict(ok, mode=""), expect=400, field="mode"),
        S("sweep: mode in capitals", dict(ok, mode="ZIP"), expect=400, field="mode"),
        S("sweep: mode with a space", dict(ok, mode="zip "), expect=400, field="mode"),
        S("sweep: mode with a NUL", dict(ok, mode="zip\u0000"), expect=400, field="mode"),
        S("sweep: mode a number", dict(ok, mode=1), expect=400, field="mode"),
        S("sweep: mode a list", dict(ok, mode=["zip"]), expect=400, field="mode"),
        S("sweep: mode null", dict(ok, mode=None), expect=(201, 400), field="mode"),
        S("sweep: zip of lists of different lengths", {"spec": two, "mode": "zip",
                                                       "vary": {"label": ["a", "b"], "loading.rate_number": [0.1]}},
          expect=400, check=field_starts("vary.")),
        # Too many jobs: at most 1000 (max_jobs_per_sweep).
        S("sweep: product of 1,331 jobs", dict(ok, vary={"label": [str(i) for i in range(11)],
                                                         "loading.rate_number": [0.1 - 0.001 * i for i in range(11)],
                                                         "output.curve_points": list(range(1, 12))}),
          expect=400, field="vary", code="out_of_range"),
        S("sweep: product of 1,001 jobs", dict(ok, vary={"label": [str(i) for i in range(7)],
                                                         "output.curve_points": list(range(1, 144))}),
          expect=400, field="vary", code="out_of_range"),
        S("sweep: zip of 1,001 jobs", dict(ok, mode="zip", vary={"output.curve_points": list(range(1, 1002))}),
          expect=400, field="vary", code="out_of_range"),
        S("sweep: product of 10^60 jobs", dict(ok, vary={f"k{i}": list(range(100)) for i in range(30)}),
          expect=400, field="vary"),
        S("sweep: one list of 150,000 values", dict(ok, vary={"output.curve_points": [1] * 150000}), expect=400,
          field="vary"),
        # label.
        S("sweep: label 201 characters", dict(ok, label="x" * 201), expect=400, field="label"),
        S("sweep: label 201 two-byte characters", dict(ok, label="\u00e9" * 201), expect=400, field="label"),
        S("sweep: label 900 KB", dict(ok, label="x" * 900000), expect=400, field="label"),
        S("sweep: label a number", dict(ok, label=5), expect=400, field="label"),
        S("sweep: label a list", dict(ok, label=["a"]), expect=400, field="label"),
        S("sweep: label null", dict(ok, label=None), expect=(201, 400), field="label"),
        # Nesting.
        S("sweep: nested 70 deep", b'{"spec": ' + b"[" * 70 + b"]" * 70 + b"}", expect=400, code="too_deep"),
        S("sweep: nested 100000 deep", b"[" * 100000 + b"]" * 100000, expect=400, code="too_deep"),
        S("sweep: a list value nested 70 deep", dict(ok, vary={"label": [deep(70)]}), expect=400, code="too_deep",
          check=field_starts("vary.")),
        S("sweep: a list value nested 10 deep", dict(ok, vary={"label": [deep(10)]}), expect=400, field="vary.label"),
        S("sweep: spec nested 70 deep", dict(ok, spec={"grain": {"size": deep(70)}}), expect=400, code="too_deep",
          check=field_starts("spec.")),
        S("sweep: vary as deep objects", dict(ok, vary={"a": {"b": {"c": {"d": [1]}}}}), expect=400, field="vary.a"),
        # Valid small sweeps (their jobs are cancelled at once).
        S("sweep: product of 2 two-cube jobs", ok, expect=201,
          check=json_holds(id=lambda v: isinstance(v, int), jobs=lambda v: len(v) == 2)),
        S("sweep: zip of 2 jobs over 2 keys, labelled", {"spec": two, "mode": "zip", "label": "zip <&> sweep",
                                                        "vary": {"loading.rate_number": [0.05, 0.1],
                                                                 "output.curve_points": [3, 4]}},
          expect=201, check=json_holds(jobs=lambda v: len(v) == 2)),
        S("sweep: product 2 x 2 of crystal jobs", {"spec": crystal, "mode": "product",
                                                   "vary": {"crystal.grains_x": [1, 2], "label": ["a", "b"]}},
          expect=201, check=json_holds(jobs=lambda v: len(v) == 4)),
        S("sweep: a whole section varied", {"spec": two, "vary": {"grain": [{"edge_spheres": 2}, None]}}, expect=201),
        S("sweep: label of 200 two-byte characters", dict(ok, label="\u00e9" * 200), expect=201),
        S("sweep: one job", dict(ok, vary={"label": ["only"]}), expect=201,
          check=json_holds(jobs=lambda v: len(v) == 1)),
    ]
    # POST /v1/sweeps?priority=: checked like POST /v1/jobs (the body is valid).
    for v in ["high", "%FF", "", "-101", "101", "1.5", "99999999999999999999", "+1"]:
        c.append(S(f"sweep: ?priority={v}", ok, query=f"?priority={v}", expect=400, field="priority"))
    c.append(S("sweep: ?priority=-100", ok, query="?priority=-100", expect=201))
    c.append(S("sweep: unknown parameter", ok, query="?dry_run=true", expect=400, field="dry_run",
               code="unknown_parameter"))
    c.append(S("sweep: unknown parameter and a bad body", b"{{{", query="?junk=%FF", expect=400, field="junk"))
    for case in c:
        assert len(case.body) < MAX_BODY, (case.name, len(case.body))
    return c


def set_path(doc, dotted, value):
    """`doc` with the field at `dotted` (grain.size, crystal.knockout_regions[].x) set to `value`."""
    parts = dotted.split(".")
    node = doc
    for k, part in enumerate(parts):
        last = k == len(parts) - 1
        if part.endswith("[]"):  # an array of objects: one valid element holding the rest
            item = {} if part[:-2] in ONE_OF else valid_element(part[:-2])
            node[part[:-2]] = [item]
            node = item
            continue
        if last:
            node[part] = value
        else:
            if not isinstance(node.get(part), dict):
                node[part] = {}
            node = node[part]
    return doc


def dotted_name(dotted):
    return dotted.replace("[]", "[0]")


def field_cases(experiments):
    """Every field of every experiment: wrong types, null, out-of-range values, NaN/Infinity tokens, 1e400,
    huge integers, wrong elements and too many items."""
    cases = []
    for e in experiments:
        exp = e["name"]
        for f in e["fields"]:
            name, kind = f["field"], f["type"]
            if name == "experiment":
                continue  # its own cases in document_cases()
            where = dotted_name(name)
            bad, invalid_json = [], []  # (label, value, acceptable error fields)
            wrong_types = [("string", "x"), ("bool", True), ("array", []), ("object", {})]
            lo, hi = f.get("minimum"), f.get("maximum")
            if kind in ("number", "integer"):
                bad += [(label, v, (where,)) for label, v in wrong_types]
                bad += [("1e400", raw("1e400"), (where,)), ("-1e400", raw("-1e400"), (where,)),
                        ("huge integer", raw("123456789012345678901234567890"), (where,)),
                        ("huge negative integer", raw("-123456789012345678901234567890"), (where,)),
                        ("2^63", raw("9223372036854775808"), (where,)),
                        ("2^64", raw("18446744073709551616"), (where,)),
                        ("1e308", 1e308, (where,))]
                if lo is not None:
                    bad.append(("below minimum", lo - 1 - abs(lo), (where,)))
                    if f.get("exclusive_minimum"):
                        bad.append(("exclusive minimum itself", lo, (where,)))
                if hi is not None:
                    bad.append(("above maximum", hi * 10 + 1, (where,)))
                    if kind == "integer":
                        bad.append(("maximum + 1", hi + 1, (where,)))
                if kind == "integer":
                    bad += [("fraction", 2.5, (where,)), ("integral 1e20", 1e20, (where,)),
                            ("-2^63 - 1", raw("-9223372036854775809"), (where,))]
                invalid_json += [("NaN token", raw("NaN")), ("Infinity token", raw("Infinity")),
                                 ("-Infinity token", raw("-Infinity")), ("hex", raw("0x10")),
                                 ("leading plus", raw("+1")), ("leading zeros", raw("007")),
                                 ("bare dot", raw(".5")), ("trailing dot", raw("1."))]
            elif kind == "string":
                bad += [("number", 1, (where,)), ("bool", True, (where,)), ("array", [], (where,)),
                        ("object", {}, (where,)), ("array of strings", ["x"], (where,)), ("1e400", raw("1e400"), (where,))]
                if "choices" in f:
                    bad += [("unknown choice", "no-such-choice", (where,)), ("empty choice", "", (where,)),
                            ("choice in capitals", f["choices"][0].upper(), (where,)),
                            ("choice with a space", f["choices"][0] + " ", (where,)),
                            ("choice with a NUL", f["choices"][0] + "\u0000", (where,))]
                if "max_length" in f:
                    bad.append(("one character too long", "x" * (f["max_length"] + 1), (where,)))
                invalid_json += [("NaN token", raw("NaN")), ("unquoted word", raw("cube")),
                                 ("single quotes", raw("'x'"))]
            elif kind.startswith("array"):
                bad += [("string", "x", (where,)), ("number", 1, (where,)), ("bool", True, (where,)),
                        ("object", {}, (where,))]
                element = (where, where + "[0]")  # either the array or its element
                if kind == "array of objects":
                    bad += [("element number", [1], element), ("element string", ["x"], element),
                            ("element array", [[]], element), ("element bool", [True], element),
                            ("element with an unknown key", [dict(valid_element(name.split(".")[-1], exp), bogus=1)],
                             (where + "[0].bogus",))]
                    if "max_items" in f:
                        bad.append(("too many items", [valid_element(name.split(".")[-1], exp)] * (f["max_items"] + 1), (where,)))
                else:
                    bad += [("element string", ["x"], element), ("element bool", [True], element),
                            ("element array", [[0]], element), ("element object", [{}], element),
                            ("element 1e400", [raw("1e400")], element), ("element -1e400", [raw("-1e400")], element),
                            ("element huge integer", [raw("123456789012345678901234567890")], element),
                            ("element 2^64", [raw("18446744073709551616")], element)]
                    if hi is not None:
                        bad.append(("element above maximum", [hi * 10 + 1], element))
                    if lo is not None:
                        bad.append(("element below minimum", [lo - 1], element))
                    if "ids" in kind:
                        bad += [("element fraction", [1.5], element), ("element negative", [-1], element)]
                    if "max_items" in f:
                        bad.append(("too many items", [0] * (f["max_items"] + 1), (where,)))
                    invalid_json += [("element NaN token", [raw("NaN")]), ("element Infinity token", [raw("Infinity")]),
                                     ("trailing comma", raw("[0,]")), ("unclosed", raw("[0"))]
            else:
                bad += [(label, v, (where,)) for label, v in wrong_types]
            for label, value, fields in bad:
                cases.append(post_spec(f"{exp} {name} {label}", dumps(set_path(tiny(exp), name, value)),
                                       expect=400, field=fields))
            for label, value in invalid_json:
                cases.append(post_spec(f"{exp} {name} {label}", dumps(set_path(tiny(exp), name, value)),
                                       expect=400, code="invalid_json", field=("", where)))
            # docs/api.md: a null value means the field's default, so the spec is accepted.
            cases.append(post_spec(f"{exp} {name} null (the default)", dumps(set_path(tiny(exp), name, None)),
                                   expect=(200, 201)))
    return cases


def structure_cases(experiments):
    """Per experiment: unknown keys at each object level, duplicate keys at each level, sections of the wrong
    type, fields of other experiments."""
    cases = []
    all_fields = {f["field"] for e in experiments for f in e["fields"]}
    for e in experiments:
        exp = e["name"]
        fields = [f["field"] for f in e["fields"]]
        sections = sorted({n.split(".")[0] for n in fields if "." in n})
        lists = sorted({n.split("[]")[0] for n in fields if "[]" in n})
        base_text = json.dumps(tiny(exp))
        # Unknown keys: top level, every section, every element of an array of objects.
        cases.append(post_spec(f"{exp} unknown top-level key", dumps(dict(tiny(exp), bogus=1)), expect=400,
                               field="bogus", code="unknown_field"))
        cases.append(post_spec(f"{exp} unknown key with a null value", dumps(dict(tiny(exp), bogus=None)),
                               expect=400, field="bogus", code="unknown_field"))
        for s in sections:
            doc = tiny(exp)
            doc.setdefault(s, {})["bogus"] = 1
            cases.append(post_spec(f"{exp} unknown key in {s}", dumps(doc), expect=400, field=f"{s}.bogus",
                                   code="unknown_field"))
            for label, value in [("number", 5), ("string", "fast"), ("array", []), ("bool", False)]:
                cases.append(post_spec(f"{exp} section {s} is a {label}", dumps(dict(tiny(exp), **{s: value})),
                                       expect=400, field=s, code="wrong_type"))
            cases.append(post_spec(f"{exp} section {s} is null (the defaults)", dumps(dict(tiny(exp), **{s: None})),
                                   expect=(200, 201)))
            # A section given twice, and a key given twice inside it.
            first = next(n.split(".", 1)[1] for n in fields if n.startswith(s + ".") and "[]" not in n)
            inner = json.dumps(tiny(exp).get(s, {}))
            text = base_text[:-1] + f', "{s}": {inner}}}'
            if s not in tiny(exp):
                text = base_text[:-1] + f', "{s}": {{}}, "{s}": {{}}}}'
            cases.append(post_spec(f"{exp} section {s} given twice", text.encode(), expect=400, field=s,
                                   code="duplicate_field"))
            doc = tiny(exp)
            doc.pop(s, None)
            text = json.dumps(doc)[:-1] + f', "{s}": {{"{first}": null, "{first}": null}}}}'
            cases.append(post_spec(f"{exp} {s}.{first} given twice", text.encode(), expect=400, field=f"{s}.{first}",
                                   code="duplicate_field"))
        for lst in lists:
            section, key = lst.split(".", 1)
            doc = tiny(exp)
            doc.setdefault(section, {})[key] = [valid_element(key, exp), dict(valid_element(key, exp), bogus=True)]
            cases.append(post_spec(f"{exp} unknown key in {lst}[1]", dumps(doc), expect=400, field=f"{lst}[1].bogus",
                                   code="unknown_field"))
            doc = tiny(exp)
            doc.setdefault(section, {})[key] = ["@@"]
            text = json.dumps(doc).replace('"@@"', '{"x": 0, "x": 1}')
            cases.append(post_spec(f"{exp} {lst}[0].x given twice", text.encode(), expect=400, field=f"{lst}[0].x",
                                   code="duplicate_field"))
        cases.append(post_spec(f"{exp} label given twice", (base_text[:-1] + ', "label": "a", "label": "b"}').encode(),
                               expect=400, field="label", code="duplicate_field"))
        cases.append(post_spec(f"{exp} experiment given twice", (base_text[:-1] + f', "experiment": "{exp}"}}').encode(),
                               expect=400, field="experiment", code="duplicate_field"))
        # Fields of the other experiments: unknown here (the section itself when this experiment has none).
        for other in sorted(all_fields - set(fields)):
            section = other.split(".")[0]
            want = other.replace("[]", "") if section in sections else section
            value = 1 if "[]" not in other else None
            doc = set_path(tiny(exp), other, value) if value is not None else None
            if doc is None:
                continue
            cases.append(post_spec(f"{exp} field of another experiment {other}", dumps(doc), expect=400,
                                   field=want, code="unknown_field"))
    return cases


def document_cases():
    """Malformed documents, whole-body problems, and the spec's top-level `experiment` field."""
    deep_array = lambda n: ("[" * n + "]" * n).encode()
    deep_object = lambda n: (b'{"a":' * n + b"1" + b"}" * n)
    two = tiny("two_cube_sliding")
    two_text = json.dumps(two)
    c = [
        post_spec("empty body", b"", expect=400, code="invalid_json"),
        post_spec("whitespace only", b"   \n\t ", expect=400, code="invalid_json"),
        post_spec("top level null", b"null", expect=400, field=""),
        post_spec("top level number", b"42", expect=400, field=""),
        post_spec("top level 1e400", b"1e400", expect=400),
        post_spec("top level string", b'"two_cube_sliding"', expect=400, field=""),
        post_spec("top level true", b"true", expect=400, field=""),
        post_spec("top level empty array", b"[]", expect=400, field=""),
        post_spec("top level array of the spec", ("[" + two_text + "]").encode(), expect=400, field=""),
        post_spec("truncated object", two_text[:-1].encode(), expect=400, code="invalid_json"),
        post_spec("truncated string", b'{"label": "abc', expect=400, code="invalid_json"),
        post_spec("trailing garbage", (two_text + " xyz").encode(), expect=400, code="invalid_json"),
        post_spec("two documents", (two_text + two_text).encode(), expect=400, code="invalid_json"),
        post_spec("trailing comma", (two_text[:-1] + ",}").encode(), expect=400, code="invalid_json"),
        post_spec("missing colon", b'{"label" "x"}', expect=400, code="invalid_json"),
        post_spec("single quotes", b"{'label': 'x'}", expect=400, code="invalid_json"),
        post_spec("unquoted key", b"{label: 1}", expect=400, code="invalid_json"),
        post_spec("comment", b'{"label": "x" /* c */}', expect=400, code="invalid_json"),
        post_spec("line comment", b'{"label": "x"} // c', expect=400, code="invalid_json"),
        post_spec("NaN token as the label", b'{"label": NaN}', expect=400, code="invalid_json"),
        post_spec("Infinity token at the top", b"Infinity", expect=400, code="invalid_json"),
        post_spec("raw newline in a string", b'{"label": "a\nb"}', expect=400, code="invalid_json"),
        post_spec("raw tab in a string", b'{"label": "a\tb"}', expect=400, code="invalid_json"),
        post_spec("NUL byte in a string", b'{"label": "a\x00b"}', expect=400, code="invalid_json"),
        post_spec("NUL byte after the document", two_text.encode() + b"\x00", expect=400, code="invalid_json"),
        post_spec("NUL byte then garbage after the document", two_text.encode() + b"\x00garbage{{{", expect=400,
                  code="invalid_json"),
        post_spec("bad escape", b'{"label": "\\x41"}', expect=400, code="invalid_json"),
        post_spec("short unicode escape", b'{"label": "\\u12"}', expect=400, code="invalid_json"),
        post_spec("lone high surrogate escape", b'{"label": "\\ud800"}', expect=400, code="invalid_json"),
        post_spec("lone low surrogate escape", b'{"label": "\\udc00"}', expect=400, code="invalid_json"),
        post_spec("escaped NUL in the label", b'{"experiment": "two_cube_sliding", "label": "a\\u0000b"}', expect=None),
        # Invalid UTF-8: docs/api.md, `invalid_json` also for invalid UTF-8.
        post_spec("invalid UTF-8 in a string (ff fe)", b'{"label": "\xff\xfe"}', expect=400, code="invalid_json"),
        post_spec("invalid UTF-8 in a key (c3 28)", b'{"\xc3\x28": 1}', expect=400, code="invalid_json"),
        post_spec("invalid UTF-8 in a nested key", b'{"grain": {"size\xff": 0.01}}', expect=400, code="invalid_json"),
        post_spec("invalid UTF-8 in a choice", b'{"experiment": "two_cube_sliding\xc0"}', expect=400, code="invalid_json"),
        post_spec("overlong UTF-8 (c0 af)", b'{"label": "\xc0\xaf"}', expect=400, code="invalid_json"),
        post_spec("UTF-8 surrogate (ed a0 80)", b'{"label": "\xed\xa0\x80"}', expect=400, code="invalid_json"),
        post_spec("UTF-8 beyond U+10FFFF (f4 90 80 80)", b'{"label": "\xf4\x90\x80\x80"}', expect=400, code="invalid_json"),
        post_spec("truncated UTF-8 sequence", b'{"label": "\xe2\x82"}', expect=400, code="invalid_json"),
        post_spec("continuation byte alone", b'{"label": "\x80"}', expect=400, code="invalid_json"),
        post_spec("invalid UTF-8 outside strings", b'{"label": "x"}\xff', expect=400, code="invalid_json"),
        post_spec("Latin-1 label", '{"label": "caf\u00e9"}'.encode("latin-1"), expect=400, code="invalid_json"),
        post_spec("UTF-16 body", json.dumps(two).encode("utf-16"), expect=400, code="invalid_json"),
        post_spec("UTF-8 byte-order mark", b"\xef\xbb\xbf" + two_text.encode(), expect=None),
        # Nesting: 64 levels are allowed (docs/api.md), deeper is `too_deep`, never a stack overflow.
        post_spec("nesting 64 (allowed; not an object)", deep_array(64), expect=400, code="wrong_type"),
        post_spec("nesting 65", deep_array(65), expect=400, code="too_deep"),
        post_spec("nesting 70", deep_array(70), expect=400, code="too_deep"),
        post_spec("nesting 100000", deep_array(100000), expect=400, code="too_deep"),
        post_spec("nesting 100000 unclosed", b"[" * 100000, expect=400, code=("too_deep", "invalid_json")),
        post_spec("nesting 500000 (1 MB less a little)", deep_array(500000)[:MAX_BODY - 10], expect=400,
                  code=("too_deep", "invalid_json")),
        post_spec("objects nested 70", deep_object(70), expect=400, code="too_deep"),
        post_spec("objects nested 100000", deep_object(100000), expect=400, code="too_deep"),
        post_spec("label nested 70", b'{"label": ' + deep_array(70) + b"}", expect=400, code="too_deep",
                  field=("label",) + tuple("label" + "[0]" * k for k in range(1, 70))),
        post_spec("label nested 10", b'{"experiment": "two_cube_sliding", "label": ' + deep_array(10) + b"}",
                  expect=400, field="label", code="wrong_type"),
        post_spec("grain.size nested 70", b'{"grain": {"size": ' + deep_array(70) + b"}}", expect=400, code="too_deep"),
        # Big documents under the 1 MiB limit.
        post_spec("900 KB array as the label", json.dumps({"experiment": "two_cube_sliding",
                                                           "label": ["x"] * 180000}).encode(),
                  expect=400, field="label"),
        post_spec("900 KB string as the label", json.dumps({"experiment": "two_cube_sliding",
                                                            "label": "x" * 900000}).encode(),
                  expect=400, field="label"),
        post_spec("900 KB object as the label", json.dumps({"experiment": "two_cube_sliding",
                                                            "label": {f"k{i}": 0 for i in range(70000)}}).encode(),
                  expect=400, field="label"),
        post_spec("900 KB of 1e400 numbers", json.dumps({"experiment": "crystal_compression",
                                                         "crystal": {"knockout": ["@"] * 125000}}).replace('"@"', "1e400")
                  .encode(), expect=400, field=("crystal.knockout", "crystal.knockout[0]")),
        post_spec("70000 unknown keys", json.dumps({f"k{i}": 0 for i in range(70000)}).encode(), expect=400,
                  code="unknown_field"),
        post_spec("valid spec padded to 900 KB with whitespace",
                  (two_text[:-1] + " " * 900000 + "}").encode(), expect=(200, 201)),
        # The top-level `experiment` field.
        post_spec("experiment unknown", b'{"experiment": "no_such_experiment"}', expect=400, field="experiment"),
        post_spec("experiment empty", b'{"experiment": ""}', expect=400, field="experiment"),
        post_spec("experiment in capitals", b'{"experiment": "TWO_CUBE_SLIDING"}', expect=400, field="experiment"),
        post_spec("experiment number", b'{"experiment": 3}', expect=400, field="experiment"),
        post_spec("experiment bool", b'{"experiment": true}', expect=400, field="experiment"),
        post_spec("experiment array", b'{"experiment": ["two_cube_sliding"]}', expect=400, field="experiment"),
        post_spec("experiment object", b'{"experiment": {}}', expect=400, field="experiment"),
        post_spec("experiment 1e400", b'{"experiment": 1e400}', expect=400, field="experiment"),
        post_spec("experiment NaN token", b'{"experiment": NaN}', expect=400, code="invalid_json"),
        post_spec("experiment with crystal fields of another", b'{"experiment": "two_cube_sliding", '
                  b'"crystal": {"grains_x": 2}}', expect=400, field="crystal", code="unknown_field"),
        post_spec("experiment null (the default)", json.dumps(dict(two, experiment=None)).encode(), expect=(200, 201)),
        post_spec("label 200 characters (the limit)", json.dumps(dict(two, label="x" * 200)).encode(), expect=(200, 201)),
        post_spec("label with an escaped NUL and quotes", json.dumps(dict(two, label='a"\\\u0001b')).encode(),
                  expect=(200, 201)),
    ]
    for case in c:  # the big documents test the parser, not the size limit
        assert len(case.body) < MAX_BODY, (case.name, len(case.body))
    return c


class BadInputTest(unittest.TestCase):
    # -- the daemon ---------------------------------------------------------------------------------------------
    def start_daemon(self):
        self.proc = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", self.db, "--workers", "1",
                                      "--threads", "1"], stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 20
        while time.time() < deadline:
            if self.proc.poll() is not None:
                break
            if self.health_status(timeout=1) == 200:
                return
            time.sleep(0.05)
        self.fail(f"granulabd did not start ({DAEMON}): {self.log_tail()}")

    def stop_daemon(self):
        if self.proc and self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=10)

    def log_tail(self, lines=8):
        self.log.flush()
        with open(self.log.name, errors="replace") as f:
            return " | ".join(f.read().splitlines()[-lines:])

    def setUp(self):
        self.assertTrue(os.access(DAEMON, os.X_OK), f"no daemon binary at {DAEMON} (set GRANULABD)")
        self.dir = tempfile.mkdtemp(prefix="granulab_bad_input_")
        self.db = os.path.join(self.dir, "jobs.db")
        self.port = free_port()
        self.log = open(os.path.join(self.dir, "daemon.log"), "w+")
        self.proc = None
        self.start_daemon()

    def tearDown(self):
        self.stop_daemon()
        self.log.close()
        shutil.rmtree(self.dir, ignore_errors=True)

    # -- transports ---------------------------------------------------------------------------------------------
    def http(self, method, path, body=None, headers=None, timeout=HTTP_TIMEOUT):
        """(status, headers, body) through http.client; status None and the error's text when nothing came."""
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        try:
            conn.request(method, path, body=body, headers=headers or {})
            r = conn.getresponse()
            data = r.read()
            return r.status, {k.lower(): v for k, v in r.getheaders()}, data
        except (OSError, http.client.HTTPException) as e:
            return None, {}, f"{type(e).__name__}: {e}".encode()
        finally:
            conn.close()

    def health_status(self, timeout=5):
        return self.http("GET", "/v1/health", timeout=timeout)[0]

    @staticmethod
    def parse_response(buf):
        """The final (non-1xx) response in `buf`: (status, headers, body, complete, interim statuses), or None."""
        pos, interim = 0, []
        while True:
            end = buf.find(b"\r\n\r\n", pos)
            if end < 0:
                return None
            lines = buf[pos:end].decode("latin-1").split("\r\n")
            try:
                status = int(lines[0].split(" ", 2)[1])
            except (IndexError, ValueError):
                return -1, {}, buf[pos:], True, interim  # not HTTP at all
            headers = {}
            for line in lines[1:]:
                if ":" in line:
                    k, v = line.split(":", 1)
                    headers[k.strip().lower()] = v.strip()
            if 100 <= status < 200:
                interim.append(status)
                pos = end + 4
                continue
            try:
                length = int(headers.get("content-length", "0"))
            except ValueError:
                length = 0
            body = buf[end + 4:end + 4 + length]
            return status, headers, body, len(body) == length, interim

    def raw_exchange(self, pieces, timeout=RAW_TIMEOUT, continue_wait=0.0):
        """Sends `pieces` on one connection, reading between them (a server may answer and close before the
        rest is sent); stops sending once a final answer came or the connection broke. With continue_wait,
        waits up to that long after the first piece for an interim `100 Continue`.
        Returns (status or None, headers, body, interim statuses)."""
        buf = b""
        deadline = time.time() + timeout
        with socket.create_connection(("127.0.0.1", self.port), timeout=timeout) as s:
            def pump(wait):
                nonlocal buf
                end = time.time() + wait
                while True:
                    left = max(0.0, end - time.time())
                    if not select.select([s], [], [], left)[0]:
                        return True
                    try:
                        chunk = s.recv(65536)
                    except OSError:
                        return False
                    if not chunk:
                        return False
                    buf += chunk
                    got = self.parse_response(buf)
                    if got and got[3]:
                        return False
                    if wait == 0 or (continue_wait and b" 100 " in buf):
                        return True
            open_ = True
            for k, piece in enumerate(pieces):
                try:
                    s.sendall(piece)
                except OSError:
                    break
                open_ = pump(continue_wait if (k == 0 and continue_wait) else 0.005)
                if not open_:
                    break
            while open_ and time.time() < deadline:
                got = self.parse_response(buf)
                if got and got[3]:
                    break
                open_ = pump(min(0.2, max(0.0, deadline - time.time())))
        got = self.parse_response(buf)
        if not got:
            return None, {}, (buf or b"no answer within %.1f s" % timeout), []
        status, headers, body, complete, interim = got
        return status, headers, body, interim

    # -- one case -----------------------------------------------------------------------------------------------
    def run_case(self, case):
        started = time.time()
        interim = []
        if case.pieces is not None:
            status, headers, body, interim = self.raw_exchange(case.pieces, continue_wait=case.continue_wait)
        else:
            status, headers, body = self.http(case.method, case.path, case.body, case.headers)
        self.elapsed[case.name] = time.time() - started
        return status, headers, body, interim

    def cancel_created(self, case, status, body):
        """A job or sweep a case created (an accepted spec) is cancelled at once: the suite runs no simulation."""
        route = case.path.split("?")[0]
        if status not in (200, 201) or case.method != "POST" or route not in ("/v1/jobs", "/v1/sweeps"):
            return
        try:
            answer = json.loads(body)
        except ValueError:
            return
        if isinstance(answer, dict) and "id" in answer and not answer.get("reused"):
            what = "jobs" if route == "/v1/jobs" else "sweeps"
            self.http("POST", f"/v1/{what}/{answer['id']}/cancel", b"", {"Content-Length": "0"})

    def judge(self, case, status, headers, body, interim):
        short = body[:300]
        if status is None:
            if case.no_answer_ok:
                return
            self.fail(f"no answer: {short!r}")
        self.assertGreaterEqual(status, 100, f"not an HTTP answer: {short!r}")
        self.assertLess(status, 500, f"5xx: {status} {short!r}")
        if case.expect is not None:
            expected = case.expect if isinstance(case.expect, tuple) else (case.expect,)
            self.assertIn(status, expected, f"status {status}, expected {case.expect}: {short!r}")
        parsed = None
        if 400 <= status < 500 and case.method != "HEAD":
            try:
                parsed = json.loads(body)
            except ValueError:
                self.fail(f"{status} whose body is not JSON: {short!r}")
            self.assertIsInstance(parsed, dict, f"{status}: {short!r}")
            error = parsed.get("error")
            self.assertIsInstance(error, dict, f"{status} without an 'error' object: {short!r}")
            for key in ("code", "message"):
                self.assertIsInstance(error.get(key), str, f"error.{key}: {short!r}")
                self.assertTrue(error[key], f"empty error.{key}: {short!r}")
            self.assertIsInstance(error.get("field"), str, f"error.field missing or not a string: {short!r}")
            if case.code is not None:
                codes = case.code if isinstance(case.code, tuple) else (case.code,)
                self.assertIn(error["code"], codes, f"error.code {error['code']!r}, expected {case.code}: "
                                                    f"{error['message'][:200]}")
            if case.field is not None:
                fields = case.field if isinstance(case.field, tuple) else (case.field,)
                self.assertIn(error["field"], fields, f"error.field {error['field']!r}, expected "
                                                      f"{fields[0]!r}: {error['message'][:200]}")
        if case.check is not None:
            case.check(self, status, headers, body, interim)

    # -- the suite ----------------------------------------------------------------------------------------------
    def fixtures(self):
        """Two finished jobs: a two-cube run (a curve, no snapshot) and a crystal compression (snapshots)."""
        ids = []
        for exp in ("two_cube_sliding", "crystal_compression"):
            status, _, body = self.http("POST", "/v1/jobs", json.dumps(tiny(exp)).encode(),
                                        {"Content-Type": "application/json"})
            self.assertEqual(status, 201, body[:300])
            ids.append(json.loads(body)["id"])
        self.wait_finished(ids, time.time() + 60)
        status, _, body = self.http("GET", f"/v1/jobs/{ids[1]}/snapshots")
        snapshots = json.loads(body)["snapshots"] if status == 200 else []
        return ids[0], ids[1], len(snapshots)

    def wait_finished(self, ids, deadline):
        for job in ids:
            while True:
                status, _, body = self.http("GET", f"/v1/jobs/{job}")
                state = json.loads(body)["status"] if status == 200 else None
                if state in ("succeeded", "failed", "cancelled") or time.time() > deadline:
                    break
                time.sleep(0.02)
            self.assertEqual(state, "succeeded", f"fixture job {job}: {body[:300]!r}")

    def submit_sweep(self, doc, query=""):
        status, _, body = self.http("POST", "/v1/sweeps" + query, json.dumps(doc).encode(),
                                    {"Content-Type": "application/json"})
        self.assertEqual(status, 201, body[:300])
        answer = json.loads(body)
        return answer["id"], answer["jobs"]

    def sweep_fixtures(self, crystal):
        """What the sweep, picture and export cases need besides the two finished jobs:
        - `sweep`: a finished sweep of two tiny two-cube jobs whose labels hold < & " ';
        - `nasty`: a finished crystal sweep whose labels hold control characters and U+FFFF (the SVGs must parse);
        - `layers`: how many {111} layers snapshot 0 of the crystal job has (its last valid ?slice= + 1);
        - `blocker`: a long job running with priority 100 (cancelled by the first cases), behind which
          `queued` (a job) and `queued_sweep` (two jobs) wait with priority -100: the single worker is busy, so
          they are queued for sure until the cases cancel them."""
        two, crystal_spec = tiny("two_cube_sliding"), tiny("crystal_compression")
        fx = {}
        fx["sweep"], fx["sweep_jobs"] = self.submit_sweep({"spec": two, "label": "sweep <&> \"q\" 'a'",
                                                           "vary": {"loading.rate_number": [0.05, 0.1]}})
        # Its first job's label holds < & ]]> and control characters (XML 1.0 forbids those: dropped), its second's
        # U+FFFF, which XML 1.0 forbids too (it used to be kept: the second job's curve.svg, snapshot SVG and archive,
        # and the sweep's curves.svg, did not parse).
        fx["nasty"], fx["nasty_jobs"] = self.submit_sweep({"spec": crystal_spec, "label": "nasty <b>&amp;\u0001\u001b",
                                                           "vary": {"label": ["a<b&c\u0001\u001f]]>", "x\uffffy"]}})
        self.wait_finished(fx["sweep_jobs"] + fx["nasty_jobs"], time.time() + 60)
        layers = 0
        while layers < 50 and self.http("GET", f"/v1/jobs/{crystal}/snapshots/0.svg?slice={layers}")[0] == 200:
            layers += 1
        fx["layers"] = layers
        # The blocker: two cubes at a rate 100 times slower than the tiny spec's (about 10 s), started for sure
        # before the queued job and sweep are submitted.
        blocker = set_path(tiny("two_cube_sliding"), "loading.rate_number", 1e-6)
        status, _, body = self.http("POST", "/v1/jobs?priority=100", json.dumps(blocker).encode(),
                                    {"Content-Type": "application/json"})
        self.assertEqual(status, 201, body[:300])
        fx["blocker"] = json.loads(body)["id"]
        deadline = time.time() + 20
        while json.loads(self.http("GET", f"/v1/jobs/{fx['blocker']}")[2])["status"] == "queued":
            self.assertLess(time.time(), deadline, "the blocker job never started")
            time.sleep(0.005)
        status, _, body = self.http("POST", "/v1/jobs?priority=-100", json.dumps(two).encode(),
                                    {"Content-Type": "application/json"})
        self.assertEqual(status, 201, body[:300])
        fx["queued"] = json.loads(body)["id"]
        fx["queued_sweep"], fx["queued_sweep_jobs"] = self.submit_sweep(
            {"spec": two, "vary": {"label": ["q1", "q2"]}}, "?priority=-100")
        status, _, body = self.http("GET", f"/v1/jobs/{fx['blocker']}")
        self.assertEqual(json.loads(body)["status"], "running", "the blocker finished too soon: the queued cases "
                                                                 "would not be deterministic")
        return fx

    def queued_cases(self, fx):
        """Run first, while the blocker runs: a queued job and sweep, then the same cancelled before they started.
        docs/api.md: curve.svg is 409 while queued (and a job cancelled before it started has no rows either)."""
        x, q, b = fx["queued"], fx["queued_sweep"], fx["blocker"]
        C = Case
        cancel = lambda name, path, expect, **kw: Case(name, "POST", path, b"", {"Content-Length": "0"}, expect=expect,
                                                       **kw)
        return [
            C("queued job: curve.svg", "GET", f"/v1/jobs/{x}/curve.svg", expect=409, code="wrong_state"),
            C("queued job: curve", "GET", f"/v1/jobs/{x}/curve", expect=409, code="wrong_state"),
            C("queued job: curve.svg with a junk parameter", "GET", f"/v1/jobs/{x}/curve.svg?format=png", expect=400,
              field="format", code="unknown_parameter"),
            C("queued job: archive", "GET", f"/v1/jobs/{x}/archive", expect=200,
              check=tar_holds(x, ["spec.json"], ["summary.json", "curve.csv", "curve.svg"])),
            C("queued job: snapshots/0.svg", "GET", f"/v1/jobs/{x}/snapshots/0.svg", expect=404, code="not_found"),
            C("queued job: snapshots/0.svg?field=bogus", "GET", f"/v1/jobs/{x}/snapshots/0.svg?field=bogus",
              expect=400, field="field"),
            C("queued job: snapshots/0?format=vtk", "GET", f"/v1/jobs/{x}/snapshots/0?format=vtk", expect=404,
              code="not_found"),
            C("queued sweep: GET", "GET", f"/v1/sweeps/{q}", expect=200,
              check=json_holds(id=q, counts={"queued": 2}, jobs=lambda v: [j["status"] for j in v] == ["queued"] * 2)),
            C("queued sweep: curves.svg", "GET", f"/v1/sweeps/{q}/curves.svg", expect=200, check=svg_parses),
            C("queued sweep: curve.svg of a job", "GET", f"/v1/jobs/{fx['queued_sweep_jobs'][0]}/curve.svg", expect=409,
              code="wrong_state"),
            cancel("queued sweep: cancel", f"/v1/sweeps/{q}/cancel", 200,
                   check=json_holds(id=q, cancelled=2, cancel_requested=0)),
            cancel("queued sweep: cancel again", f"/v1/sweeps/{q}/cancel", 200,
                   check=json_holds(cancelled=0, cancel_requested=0)),
            C("cancelled sweep: GET", "GET", f"/v1/sweeps/{q}", expect=200, check=json_holds(counts={"cancelled": 2})),
            C("cancelled sweep: curves.svg", "GET", f"/v1/sweeps/{q}/curves.svg", expect=200, check=svg_parses),
            cancel("queued job: cancel", f"/v1/jobs/{x}/cancel", 200, check=json_holds(status="cancelled")),
            C("job cancelled before it started: curve.svg", "GET", f"/v1/jobs/{x}/curve.svg", expect=409,
              code="wrong_state"),
            C("job cancelled before it started: archive", "GET", f"/v1/jobs/{x}/archive", expect=200,
              check=tar_holds(x, ["spec.json"], ["curve.csv", "curve.svg"])),
            # The running blocker: its curve so far (none yet is a 409), its archive; then cancelled.
            C("running job: curve.svg", "GET", f"/v1/jobs/{b}/curve.svg", expect=(200, 409), check=svg_parses),
            C("running job: archive", "GET", f"/v1/jobs/{b}/archive", expect=200, check=tar_holds(b, ["spec.json"])),
            cancel("running job: cancel", f"/v1/jobs/{b}/cancel", 202),
        ]

    def new_route_cases(self, done, crystal, n_snapshots, fx):
        """The sweep, picture, export and web routes: path junk, query junk, method junk and good requests."""
        d, c, s, n = done, crystal, fx["sweep"], fx["nasty"]
        missing = 999999999
        layers = fx["layers"]
        last = n_snapshots - 1
        cases = []
        short = lambda path: path if len(path) <= 90 else f"{path[:60]}... ({len(path)} characters)"
        get = lambda path, expect=None, field=None, code=None, **kw: Case(f"GET {short(path)}", "GET", path,
                                                                         expect=expect, field=field, code=code, **kw)
        post = lambda path, expect=None, field=None, code=None, **kw: Case(f"POST {short(path)}", "POST", path, b"",
                                                                          {"Content-Length": "0"}, expect=expect,
                                                                          field=field, code=code, **kw)
        svg = lambda path, **kw: get(path, 200, check=svg_parses, **kw)
        junk_ids = ["9" * 25, "99999999999999999999", "9223372036854775808", "0", str(missing), "-1", "%00", "%2D1",
                    "abc", "1.5", "+1", "%FF", "%20", "9" * 5000]

        # -- path junk: ids that are no job, no sweep, no snapshot -------------------------------------------------
        for p in junk_ids:
            for tail in ["curve.svg", "snapshots/0.svg", "snapshots/0?format=dump", "archive"]:
                cases.append(get(f"/v1/jobs/{p}/{tail}", 404, code="not_found"))
            cases.append(get(f"/v1/sweeps/{p}", 404, code="not_found"))
            cases.append(get(f"/v1/sweeps/{p}/curves.svg", 404, code="not_found"))
            cases.append(post(f"/v1/sweeps/{p}/cancel", 404, code="not_found"))
        for k in [str(n_snapshots), "9" * 25, "99999999999999999999", "2147483648", "4294967296", "-1", "%00", "abc",
                  "1.0", "%2D1", "9" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}.svg", 404, code="not_found"))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=vtk", 404, code="not_found"))
        cases.append(get(f"/v1/jobs/{d}/snapshots/0.svg", 404, code="not_found"))  # two cubes: no snapshot
        cases.append(get(f"/v1/jobs/{d}/snapshots/0?format=dump", 404, code="not_found"))
        for p in [f"/v1/jobs/{d}/curve.SVG", f"/v1/jobs/{d}/curve.svg/", f"/v1/jobs/{d}/curve.svg.svg",
                  f"/v1/jobs/{d}/curvexsvg", f"/v1/jobs/{d}/curve.png", f"/v1/jobs/{c}/snapshots/0.SVG",
                  f"/v1/jobs/{c}/snapshots/.svg", f"/v1/jobs/{c}/snapshots/0.svg.svg", f"/v1/jobs/{c}/snapshots/0.png",
                  f"/v1/jobs/{c}/snapshots/0/", f"/v1/jobs/{c}/archive/", f"/v1/jobs/{c}/archive.tar",
                  f"/v1/jobs/{c}/archives", f"/v1/sweeps/{s}/", f"/v1/sweeps/{s}/curves", f"/v1/sweeps/{s}/curve.svg",
                  f"/v1/sweeps/{s}/jobs", f"/v1/sweeps/{s}/curves.svg/x", "/v1/sweeps/", "/v1/sweep",
                  "/web/", "/web/nothing.js", "/web/app.js/", "/web/APP.JS", "/web/app.js%00", "/web/app.js.map",
                  "/web/index.html", "/index.html", "/web/" + "x" * 5000, "/v1/examples/two_cube",
                  "/v1/openapi.yaml", "/v1/openapi.json/"]:
            cases.append(get(p, 404, code="not_found"))
        cases.append(get("/v1/sweeps/" + "9" * 9000, 414))
        cases.append(get(f"/v1/jobs/{c}/snapshots/" + "9" * 9000 + ".svg", 414))

        def no_file_from_disk(test, status, headers, body, interim):
            test.assertNotIn(b"root:", body, "a file from outside the embedded ones was served")
            test.assertNotIn(b"#include", body, "a source file was served")
        for p in ["/web/../../etc/passwd", "/web/%2e%2e/%2e%2e/etc/passwd", "/web/..%2F..%2Fetc%2Fpasswd",
                  "/web/../server/web_routes.cpp", "/web//app.js", "/web/./app.js", "//web/app.js"]:
            cases.append(get(p, check=no_file_from_disk))

        # -- GET /v1/jobs/{id}/curve.svg ---------------------------------------------------------------------------
        for job in [d, c] + fx["sweep_jobs"] + fx["nasty_jobs"]:  # the second nasty one: U+FFFF
            cases.append(svg(f"/v1/jobs/{job}/curve.svg"))
        for q, field in [("format=csv", "format"), ("junk=1", "junk"), ("x", "x"), ("field=severity", "field"),
                         ("slice=0", "slice")]:
            cases.append(get(f"/v1/jobs/{d}/curve.svg?{q}", 400, field=field, code="unknown_parameter"))
        cases.append(get(f"/v1/jobs/{d}/curve.svg?%FF=1", 400, code="unknown_parameter"))

        # -- GET /v1/jobs/{id}/snapshots/{k}.svg?field=&slice= -----------------------------------------------------
        cases.append(svg(f"/v1/jobs/{c}/snapshots/0.svg"))
        if last > 0:
            cases.append(svg(f"/v1/jobs/{c}/snapshots/{last}.svg"))
        for f in ["penetration_ratio", "gamma_max", "equivalent_strain", "displacement"]:
            cases.append(svg(f"/v1/jobs/{c}/snapshots/{last}.svg?field={f}"))
            cases.append(svg(f"/v1/jobs/{c}/snapshots/0.svg?field={f}&slice={layers - 1}"))
        for k in range(layers):
            cases.append(svg(f"/v1/jobs/{c}/snapshots/0.svg?slice={k}"))
        for job in fx["nasty_jobs"]:  # the second: U+FFFF in its label
            cases.append(svg(f"/v1/jobs/{job}/snapshots/0.svg?field=penetration_ratio"))
        for v in ["bogus", "%FF", "", "severity", "PENETRATION_RATIO", "penetration_ratio%00", "penetration_ratio,gamma_max", "penetration_ratio%20", "%20penetration_ratio",
                  "gamma-max", "0", "displacement%FF", "x" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?field={v}", 400, field="field"))
        # A slice: an integer 0..2^20 (else a 400 from the parameter check), and a layer of the crystal (else a 400
        # from the picture: docs/api.md, "a layer outside the crystal is a 400 naming slice").
        for v in ["-1", "abc", "", "99999999999999999999", "9223372036854775808", "1048577", "1.5", "+1", "0x1",
                  "%00", "1e3", "%FF", "--1", "%201", "1%20", "%EF%BC%91", "-2147483648"]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?slice={v}", 400, field="slice"))
        for v in [layers, layers + 1, 1000, 1 << 20]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?slice={v}", 400, field="slice"))
        cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?field=penetration_ratio&slice={layers}", 400, field="slice"))
        cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?field=bogus&slice={layers - 1}", 400, field="field"))
        cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?slice=-0", (200, 400), field="slice", check=svg_parses))
        for q in ["slice=0&slice=0", "field=penetration_ratio&field=penetration_ratio", "slice=0&slice=99"]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?{q}", (200, 400), check=svg_parses))
        for q, field in [("format=json", "format"), ("junk=%FF", "junk"), ("field=penetration_ratio&layer=0", "layer"),
                         ("Field=penetration_ratio", "Field"), ("slices=0", "slices")]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0.svg?{q}", 400, field=field, code="unknown_parameter"))

        # -- GET /v1/jobs/{id}/snapshots/{k}?format= ---------------------------------------------------------------
        def starts(prefix):
            def check(test, status, headers, body, interim):
                test.assertTrue(body.startswith(prefix), f"does not start with {prefix!r}: {body[:80]!r}")
            return check
        for k in sorted({0, last}):
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=json", 200,
                             check=both(content_type("application/json"), lambda t, st, h, b, i: json.loads(b))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=dump", 200,
                             check=both(content_type("text/plain"), starts(b"ITEM: TIMESTEP"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=vtk", 200,
                             check=both(content_type("text/plain"), starts(b"# vtk DataFile"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=vtk_interfaces", 200,
                             check=both(content_type("text/plain"), starts(b"# vtk DataFile"))))
            for fmt in ("contacts_vtk", "mesh_vtk"):
                cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format={fmt}", 200,
                                 check=both(content_type("text/plain"), starts(b"# vtk DataFile"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=dump_spheres", 200,
                             check=both(content_type("text/plain"), starts(b"ITEM: TIMESTEP"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=contacts_dump", 200,
                             check=both(content_type("text/plain"), starts(b"ITEM: TIMESTEP"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=dic_csv", 200,
                             check=both(content_type("text/csv"), starts(b"x,z,ux,uy,uz,exx,ezz,exz,gamma_max\n"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}?format=dic_vtk&step=0.002", 200,
                             check=both(content_type("text/plain"), starts(b"# vtk DataFile"))))
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}/dic.svg?field=exz&step=0.003", 200,
                             check=content_type("image/svg+xml")))
        # The grid step: a positive number of metres, at most 1, and not so fine the map passes 250,000 nodes.
        for v in ["0", "-0.001", "nan", "inf", "1e400", "abc", "", "0.001x", "2", "1e-9", "x" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0?format=dic_csv&step={v}", 400, field="step"))
            cases.append(get(f"/v1/jobs/{c}/snapshots/0/dic.svg?step={v}", 400, field="step"))
        for v in ["severity", "", "GAMMA_MAX", "x" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0/dic.svg?field={v}", 400, field="field"))
        cases.append(get(f"/v1/jobs/{c}/snapshots/99/dic.svg", 404))
        cases.append(get(f"/v1/jobs/{c}/snapshots/0/dic.svg?slice=0", 400, field="slice", code="unknown_parameter"))
        for v in ["xml", "%FF", "", "JSON", "json%00", "dump,vtk", "vtk%20", "csv", "svg", "vtk_grains", "x" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0?format={v}", 400, field="format"))
        cases.append(get(f"/v1/jobs/{c}/snapshots/0?format=json&format=dump", (200, 400)))
        for q, field in [("field=severity", "field"), ("slice=0", "slice"), ("format=vtk&junk=1", "junk")]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0?{q}", 400, field=field, code="unknown_parameter"))

        # -- GET /v1/jobs/{id}/archive -----------------------------------------------------------------------------
        snapshot_files = [f"snapshots/snapshot_{k}{ext}" for k in range(n_snapshots)
                          for ext in (".json", ".dump", "_grains.vtk", "_interfaces.vtk", "_contacts.vtk", "_contacts.dump", "_meshes.vtk", "_dic.csv", "_dic.vtk")]
        cases.append(get(f"/v1/jobs/{d}/archive", 200,
                         check=tar_holds(d, ["spec.json", "summary.json", "curve.csv", "curve.svg"],
                                         ["snapshots/snapshot_0.json"])))
        cases.append(get(f"/v1/jobs/{c}/archive", 200,
                         check=tar_holds(c, ["spec.json", "summary.json", "curve.csv", "curve.svg"] + snapshot_files)))
        for job in fx["nasty_jobs"]:  # the second: U+FFFF in its curve.svg
            cases.append(get(f"/v1/jobs/{job}/archive", 200, check=tar_holds(job, ["spec.json", "curve.svg"])))
        for q, field in [("format=zip", "format"), ("junk", "junk"), ("gzip=true", "gzip")]:
            cases.append(get(f"/v1/jobs/{d}/archive?{q}", 400, field=field, code="unknown_parameter"))

        # -- GET /v1/sweeps ----------------------------------------------------------------------------------------
        def empty_sweeps(value):
            def check(test, status, headers, body, interim):
                answer = json.loads(body)
                test.assertEqual(answer.get("sweeps"), [], f"offset {value} listed sweeps: it wrapped around")
                test.assertEqual(answer.get("offset"), value, "the offset echoed is not the one asked for")
            return check
        cases.append(get("/v1/sweeps", 200, check=json_holds(sweeps=lambda v: s in [x["id"] for x in v], limit=50,
                                                             offset=0)))
        cases.append(get("/v1/sweeps?offset=0", 200, check=json_holds(sweeps=lambda v: len(v) >= 2)))
        for v in ["%FF", "-1", "0", "1001", "99999999999999999999", "9223372036854775808", "1e3", "", "%20", "5abc",
                  "0x10", "+5", "1.0", "--1", "%00", "%EF%BC%95"]:
            cases.append(get(f"/v1/sweeps?limit={v}", 400, field="limit"))
        cases.append(get("/v1/sweeps?limit=1", 200, check=json_holds(sweeps=lambda v: len(v) == 1, limit=1)))
        cases.append(get("/v1/sweeps?limit=1000", 200))
        for v in ["-1", "-5", "99999999999999999999", "18446744073709551616", "1099511627777", "%FF", "abc", "",
                  "1e10", "-2147483648"]:
            cases.append(get(f"/v1/sweeps?offset={v}", 400, field="offset"))
        for v in [2 ** 31, 2 ** 32 + 1, 2 ** 40]:
            cases.append(get(f"/v1/sweeps?offset={v}", 200, check=empty_sweeps(v)))
        cases.append(get("/v1/sweeps?limit=1000&offset=1000", 200, check=empty_sweeps(1000)))
        for v in ["%FF", "nobody", "%00", "a%20b", ""]:
            cases.append(get(f"/v1/sweeps?owner={v}", 200))
        cases.append(get("/v1/sweeps?owner=nobody&limit=5", 200, check=json_holds(sweeps=[])))
        cases.append(get("/v1/sweeps?owner=" + "x" * 10000, 414))
        for q, field in [("status=succeeded", "status"), ("junk=%FF", "junk"), ("mode=zip", "mode"),
                         ("limit=5&label=x", "label")]:
            cases.append(get(f"/v1/sweeps?{q}", 400, field=field, code="unknown_parameter"))
        for q in ["limit=5&limit=6", "%zz=1", "&&&", "limit=1#frag"]:
            cases.append(get(f"/v1/sweeps?{q}"))

        # -- GET /v1/sweeps/{id}, POST /v1/sweeps/{id}/cancel, GET /v1/sweeps/{id}/curves.svg -----------------------
        cases.append(get(f"/v1/sweeps/{s}", 200, check=json_holds(
            id=s, mode="product", counts={"succeeded": 2}, vary={"loading.rate_number": [0.05, 0.1]},
            spec=lambda v: v.get("experiment") == "two_cube_sliding",
            jobs=lambda v: [j["values"] for j in v] == [{"loading.rate_number": 0.05}, {"loading.rate_number": 0.1}])))
        cases.append(get(f"/v1/sweeps/{n}", 200, check=json_holds(counts={"succeeded": 2})))
        cases.append(svg(f"/v1/sweeps/{s}/curves.svg"))
        cases.append(svg(f"/v1/sweeps/{n}/curves.svg"))  # U+FFFF in a legend
        for q, field in [("limit=1", "limit"), ("format=csv", "format"), ("junk", "junk")]:
            cases.append(get(f"/v1/sweeps/{s}?{q}", 400, field=field, code="unknown_parameter"))
        for q, field in [("field=severity", "field"), ("format=png", "format"), ("junk=%00", "junk")]:
            cases.append(get(f"/v1/sweeps/{s}/curves.svg?{q}", 400, field=field, code="unknown_parameter"))
        cases.append(post(f"/v1/sweeps/{s}/cancel?force=true", 400, field="force", code="unknown_parameter"))
        cases.append(post(f"/v1/sweeps/{s}/cancel", 200, check=json_holds(id=s, cancelled=0, cancel_requested=0)))
        cases.append(Case("POST sweep cancel with a junk body", "POST", f"/v1/sweeps/{s}/cancel", b"\xff\xfe[[[",
                          {"Content-Type": "application/json"}, expect=200, check=json_holds(cancelled=0)))

        # -- GET /v1/openapi.json, /v1/examples, /, /web/app.js, /web/style.css ------------------------------------
        def documents_new_routes(test, status, headers, body, interim):
            paths = json.loads(body).get("paths", {})
            for route, method in [("/v1/sweeps", "post"), ("/v1/sweeps", "get"), ("/v1/sweeps/{id}", "get"),
                                  ("/v1/sweeps/{id}/cancel", "post"), ("/v1/sweeps/{id}/curves.svg", "get"),
                                  ("/v1/jobs/{id}/curve.svg", "get"), ("/v1/jobs/{id}/snapshots/{k}.svg", "get"),
                                  ("/v1/jobs/{id}/snapshots/{k}", "get"), ("/v1/jobs/{id}/archive", "get")]:
                test.assertIn(method, paths.get(route, {}), f"{method.upper()} {route} is not in the OpenAPI document")

        def examples_listed(test, status, headers, body, interim):
            examples = json.loads(body)["examples"]
            test.assertTrue(examples, "no example")
            for e in examples:
                test.assertIsInstance(e.get("name"), str)
                test.assertIsInstance(e.get("spec"), dict)
        cases.append(get("/v1/openapi.json", 200, check=both(content_type("application/json"), documents_new_routes)))
        cases.append(get("/v1/examples", 200, check=both(content_type("application/json"), examples_listed)))
        cases.append(Case("GET / (the web page)", "GET", "/", expect=200, check=content_type("text/html")))
        cases.append(get("/web/app.js", 200, check=content_type("text/javascript", "application/javascript")))
        cases.append(get("/web/style.css", 200, check=content_type("text/css")))
        for p in ["/v1/openapi.json", "/v1/examples"]:
            for q, field in [("junk=1", "junk"), ("v=2", "v"), ("%FF", None)]:
                cases.append(get(f"{p}?{q}", 400, field=field, code="unknown_parameter"))
        # The page's files ignore a query: a browser's cache-busting ?v=2 is not a typo to report.
        for p in ["/", "/web/app.js", "/web/style.css"]:
            for q in ["junk=1", "v=2", "%FF"]:
                cases.append(get(f"{p}?{q}", 200))

        # -- method junk -------------------------------------------------------------------------------------------
        routes = ["/v1/sweeps", f"/v1/sweeps/{s}", f"/v1/sweeps/{s}/cancel", f"/v1/sweeps/{s}/curves.svg",
                  f"/v1/jobs/{d}/curve.svg", f"/v1/jobs/{c}/snapshots/0.svg", f"/v1/jobs/{d}/archive",
                  "/v1/openapi.json", "/v1/examples", "/", "/web/app.js", "/web/style.css"]
        for route in routes:
            for method in ("PUT", "DELETE", "PATCH"):
                cases.append(Case(f"{method} {route}", method, route, expect=tuple(range(400, 500))))
        for route in [f"/v1/sweeps/{s}", f"/v1/sweeps/{s}/curves.svg", f"/v1/jobs/{d}/curve.svg",
                      f"/v1/jobs/{c}/snapshots/0.svg", f"/v1/jobs/{d}/archive", "/v1/openapi.json", "/v1/examples", "/",
                      "/web/app.js", "/web/style.css"]:
            cases.append(Case(f"POST {route}", "POST", route, b"", expect=tuple(range(400, 500))))
        cases.append(Case(f"GET /v1/sweeps/{s}/cancel", "GET", f"/v1/sweeps/{s}/cancel", expect=tuple(range(400, 500))))
        for route in [f"/v1/jobs/{d}/curve.svg", f"/v1/jobs/{c}/archive", f"/v1/sweeps/{s}/curves.svg", "/",
                      f"/v1/jobs/{c}/snapshots/0.svg?slice=abc"]:
            cases.append(Case(f"HEAD {route}", "HEAD", route))
        return cases

    def route_cases(self, done, crystal, n_snapshots):
        d, c = done, crystal
        missing = 999999999
        spec = json.dumps(tiny("two_cube_sliding")).encode()
        json_type = {"Content-Type": "application/json"}

        def empty_list(value):
            def check(test, status, headers, body, interim):
                answer = json.loads(body)
                test.assertEqual(answer.get("jobs"), [], f"offset {value} listed jobs: it wrapped around")
                test.assertEqual(answer.get("offset"), value, "the offset echoed is not the one asked for")
            return check

        def listed(test, status, headers, body, interim):
            test.assertTrue(json.loads(body)["jobs"], "offset=0 lists no job: the offset checks prove nothing")

        cases = []
        short = lambda path: path if len(path) <= 90 else f"{path[:60]}... ({len(path)} characters)"
        get = lambda path, expect=None, field=None, code=None, **kw: Case(f"GET {short(path)}", "GET", path,
                                                                         expect=expect, field=field, code=code, **kw)
        # GET /v1/jobs: limit, offset, status, owner.
        cases.append(get("/v1/jobs?offset=0", 200, check=listed))
        for v in ["%FF", "-1", "0", "1001", "99999999999999999999", "9223372036854775808", "1e3", "", "%20", "5abc",
                  "0x10", "+5", "1.0", "--1", "%00", "%EF%BC%95"]:
            cases.append(get(f"/v1/jobs?limit={v}", 400, field="limit"))
        for v in ["1", "1000"]:
            cases.append(get(f"/v1/jobs?limit={v}", 200))
        for v in ["-1", "-5", "99999999999999999999", "18446744073709551616", "1099511627777", "%FF", "abc", "",
                  "1e10", "-2147483648"]:
            cases.append(get(f"/v1/jobs?offset={v}", 400, field="offset"))
        for v in [2 ** 31, 2 ** 31 + 1, 2 ** 32, 2 ** 32 + 1, 2 ** 40]:
            cases.append(get(f"/v1/jobs?offset={v}", 200, check=empty_list(v)))
        cases.append(get(f"/v1/jobs?limit=1&offset={2 ** 31}", 200, check=empty_list(2 ** 31)))
        for v in ["bogus", "%FF%FE", "QUEUED", "succeeded,failed", "%00", "queued%00", "%20running"]:
            cases.append(get(f"/v1/jobs?status={v}", 400, field="status"))
        for v in ["succeeded", "cancelled", ""]:
            cases.append(get(f"/v1/jobs?status={v}", 200))
        for v in ["%FF", "nobody", "%00", "a%20b"]:
            cases.append(get(f"/v1/jobs?owner={v}", 200))
        cases.append(get("/v1/jobs?owner=" + "x" * 10000, 414))
        cases.append(get("/v1/jobs?" + "&".join(f"k{i}=v" for i in range(1000)), (400, 414)))  # unknown parameters
        for q in ["limit=5&limit=6", "%zz=1", "&&&", "=", "limit", "?limit=1", "limit=1#frag"]:
            cases.append(get(f"/v1/jobs?{q}"))
        # GET /v1/jobs/{id}: path junk.
        for p in ["9" * 25, "99999999999999999999", "9223372036854775808", "0", str(missing), "-1", "%00", "%2D1",
                  "abc", "1.5", "1e3", "+1", "0x1", "%FF", "1%2F..%2F..%2Fhealth", "..", "%2e%2e", "9" * 5000]:
            cases.append(get(f"/v1/jobs/{p}", 404, code="not_found"))
        cases.append(get("/v1/jobs/" + "9" * 9000, 414))
        cases.append(get("/v1/" + "x" * 20000, (414, 431)))
        for p in [f"/v1/jobs/{d}/../../health", "/v1/jobs/../v1/health", "//v1//health", "/V1/HEALTH", "/v1/health/",
                  "/v1/jobs/", f"/v1/jobs/{d}/", "/", "/v2/jobs", "/v1", "/v1/experiments/two_cube_sliding",
                  f"/v1/jobs/{d}/curve/x", f"/v1/jobs/{d}/snapshots/0/x", "/v1/jobs/%2F", "/%00"]:
            cases.append(get(p))
        # Routes under a job id, with ids that are no job.
        for p in ["9" * 25, "0", str(missing), "-1"]:
            for tail in ["curve", "curve?format=csv", "snapshots", "snapshots/0"]:
                cases.append(get(f"/v1/jobs/{p}/{tail}", 404, code="not_found"))
            cases.append(Case(f"POST /v1/jobs/{p}/cancel", "POST", f"/v1/jobs/{p}/cancel", b"", {"Content-Length": "0"},
                              expect=404, code="not_found"))
        # Curves: ?format=.
        for v in ["bogus", "%FF", "CSV", "", "json%00", "csv,json", "xml"]:
            cases.append(get(f"/v1/jobs/{d}/curve?format={v}", 400, field="format"))
        for v in ["csv", "json"]:
            cases.append(get(f"/v1/jobs/{d}/curve?format={v}", 200))
        cases.append(get(f"/v1/jobs/{d}/curve", 200))
        cases.append(Case("curve with an unknown parameter", "GET", f"/v1/jobs/{c}/curve?format=csv&junk=%FF", expect=400,
                          field="junk"))
        # Snapshots: the list, then indices.
        cases.append(get(f"/v1/jobs/{c}/snapshots", 200))
        cases.append(get(f"/v1/jobs/{d}/snapshots", 200))
        if n_snapshots:
            cases.append(get(f"/v1/jobs/{c}/snapshots/0", 200))
        for k in [str(n_snapshots), "9" * 25, "99999999999999999999", "2147483648", "4294967296", "-1", "%00", "abc",
                  "1.0", "9" * 5000]:
            cases.append(get(f"/v1/jobs/{c}/snapshots/{k}", 404, code="not_found"))
        cases.append(get(f"/v1/jobs/{d}/snapshots/0", 404, code="not_found"))
        # Cancel: a finished job is 409; junk queries are ignored.
        cases.append(Case("POST cancel of a finished job", "POST", f"/v1/jobs/{d}/cancel", b"", {"Content-Length": "0"},
                          expect=409, code="wrong_state"))
        cases.append(Case("POST cancel with a junk body", "POST", f"/v1/jobs/{d}/cancel", b"\xff\xfe[[[",
                          {"Content-Type": "application/json"}, expect=409))
        cases.append(Case("POST cancel with a query", "POST", f"/v1/jobs/{d}/cancel?force=%FF", b"", expect=400, field="force"))
        # Priority (docs/api.md): ?value= -100..100, named `value`.
        for v in ["", "x", "1000", "-101", "101", "%FF", "99999999999999999999", "1.5"]:
            q = f"?value={v}" if v != "" else ""
            cases.append(Case(f"POST priority {q or '(no value)'}", "POST", f"/v1/jobs/{d}/priority{q}", b"",
                              expect=400, field="value"))
        cases.append(Case("POST priority of a finished job", "POST", f"/v1/jobs/{d}/priority?value=5", b"", expect=409))
        # DELETE of what is no job (never of the fixtures).
        for p in ["9" * 25, "0", str(missing), "-1"]:
            cases.append(Case(f"DELETE /v1/jobs/{p}", "DELETE", f"/v1/jobs/{p}", expect=404, code="not_found"))
        # Submissions: content types, encodings and query parameters of POST /v1/jobs.
        for label, headers, expect in [
            ("text/plain", {"Content-Type": "text/plain"}, (200, 201)),
            ("no content type", {}, (200, 201)),
            ("form content type", {"Content-Type": "application/x-www-form-urlencoded"}, (200, 201)),
            ("multipart without a boundary", {"Content-Type": "multipart/form-data"}, None),
            ("multipart with a boundary", {"Content-Type": "multipart/form-data; boundary=xyz"}, None),
            ("charset utf-16", {"Content-Type": "application/json; charset=utf-16"}, (200, 201)),
            ("gzip encoding of a plain body", {"Content-Type": "application/json", "Content-Encoding": "gzip"}, None),
            ("junk encoding", {"Content-Type": "application/json", "Content-Encoding": "x-junk"}, None),
            ("junk Authorization", {"Authorization": "Bearer \x7f\x7f", **json_type}, (200, 201)),
        ]:
            cases.append(post_spec(f"POST /v1/jobs {label}", spec, headers=headers, expect=expect))
        # Content-Encoding: the 1 MiB limit holds for what the body inflates to, not only for the bytes sent
        # (a 400 KB gzip body of whitespace is a 400 MB spec). Refusing encodings (415) is as good.
        deflate = zlib.compressobj(9, zlib.DEFLATED, 31)
        bomb = deflate.compress(spec[:-1] + b" " * (2 * MAX_BODY) + b"}") + deflate.flush()
        cases.append(post_spec("POST /v1/jobs gzip body inflating to 2 MiB", bomb,
                               headers={"Content-Type": "application/json", "Content-Encoding": "gzip"},
                               expect=(413, 415)))
        cases.append(post_spec("POST /v1/jobs gzip body of a valid spec", gzip.compress(spec),
                               headers={"Content-Type": "application/json", "Content-Encoding": "gzip"},
                               expect=(200, 201, 415)))
        for q in ["priority=high", "priority=1000000000", "priority=%FF", "priority=-101", "priority=101",
                  "priority=", "priority=1.5", "priority=99999999999999999999"]:
            cases.append(Case(f"POST /v1/jobs?{q}", "POST", f"/v1/jobs?{q}", spec, json_type, expect=400,
                              field="priority"))
        for q, field in [("reuse=%00", "reuse"), ("reuse=yes", "reuse"), ("junk=%FF", "junk")]:
            cases.append(Case(f"POST /v1/jobs?{q}", "POST", f"/v1/jobs?{q}", spec, json_type, expect=400, field=field))
        cases.append(Case("POST /v1/jobs?reuse=true&reuse=false", "POST", "/v1/jobs?reuse=true&reuse=false", spec,
                          json_type, expect=(200, 201)))
        # Wrong methods on every route (DELETE /v1/jobs/{id} is a route: never sent to a fixture).
        routes = ["/v1/jobs", f"/v1/jobs/{d}", f"/v1/jobs/{d}/cancel", f"/v1/jobs/{d}/curve",
                  f"/v1/jobs/{d}/snapshots", f"/v1/jobs/{c}/snapshots/0", "/v1/experiments", "/v1/health",
                  f"/v1/jobs/{d}/priority"]
        for route in routes:
            for method in ("PUT", "DELETE", "PATCH"):
                if method == "DELETE" and route == f"/v1/jobs/{d}":
                    continue
                cases.append(Case(f"{method} {route}", method, route, expect=tuple(range(400, 500))))
        for method, route in [("POST", "/v1/health"), ("POST", "/v1/experiments"), ("POST", f"/v1/jobs/{d}"),
                              ("POST", f"/v1/jobs/{d}/curve"), ("POST", f"/v1/jobs/{d}/snapshots"),
                              ("GET", f"/v1/jobs/{d}/cancel"), ("GET", f"/v1/jobs/{d}/priority"),
                              ("OPTIONS", "/v1/jobs"), ("TRACE", "/v1/jobs"), ("CONNECT", "/v1/jobs")]:
            expect = None if method in ("OPTIONS",) else tuple(range(400, 500))
            cases.append(Case(f"{method} {route}", method, route, b"" if method == "POST" else None, expect=expect))
        cases.append(Case("HEAD /v1/health", "HEAD", "/v1/health"))
        cases.append(Case("HEAD /v1/jobs/0", "HEAD", "/v1/jobs/0"))
        cases.append(Case("experiments with unknown parameters", "GET", "/v1/experiments?junk=%FF&x", expect=400,
                          field="junk"))
        cases.append(Case("health with an unknown parameter", "GET", "/v1/health?limit=-1", expect=400, field="limit"))
        return cases

    def raw_cases(self, done):
        """Bytes no HTTP library sends: framing without Content-Length, chunked bodies, Expect, heads."""
        d = done
        spec = json.dumps(tiny("two_cube_sliding")).encode()
        post = b"POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
        chunk = b"x" * 65536

        def chunked(data, size=1000):
            out = b""
            for i in range(0, len(data), size):
                piece = data[i:i + size]
                out += b"%x\r\n" % len(piece) + piece + b"\r\n"
            return out + b"0\r\n\r\n"

        def continued(test, status, headers, body, interim):
            test.assertIn(100, interim, "no '100 Continue' before the final answer (docs/api.md: it is answered)")

        # ~20 KB: the label is capped at 200 characters, so the rest is JSON whitespace.
        padded = (spec[:-1] + b", \"label\": \"" + b"p" * 200 + b"\"" + b" " * 20000 + b"}")
        assert 20000 < len(padded) < 21000
        over = MAX_BODY // len(chunk) + 1  # chunks of 64 KiB, each under the limit, together over it
        R = lambda name, pieces, expect, **kw: Case(name, "POST" if pieces[0].startswith(b"POST") else "RAW",
                                                    "/v1/jobs" if pieces[0].startswith(b"POST /v1/jobs ") else "",
                                                    pieces=pieces, expect=expect, **kw)
        return [
            # (a) A POST with neither a body nor Content-Length has an empty body.
            R("(a) cancel without body or Content-Length", [f"POST /v1/jobs/{d}/cancel HTTP/1.1\r\nHost: x\r\n\r\n"
                                                           .encode()], 409, code="wrong_state"),
            R("(a) submit without body or Content-Length", [b"POST /v1/jobs HTTP/1.1\r\nHost: x\r\n\r\n"], 400,
              code="invalid_json"),
            R("(a) cancel, HTTP/1.0, no Content-Length", [f"POST /v1/jobs/{d}/cancel HTTP/1.0\r\n\r\n".encode()], 409),
            # (b) Bodies over the limit: 413, the daemon stays up.
            R("(b) chunked body over 1 MiB in 64 KiB chunks",
              [post + b"Transfer-Encoding: chunked\r\n\r\n"] + [b"%x\r\n" % len(chunk) + chunk + b"\r\n"] * over
              + [b"0\r\n\r\n"], 413, code="too_large"),
            R("(b) one chunk announced over 1 MiB", [post + b"Transfer-Encoding: chunked\r\n\r\n",
                                                     b"%x\r\n" % (MAX_BODY + 1), chunk], 413, code="too_large"),
            R("(b) chunk size of 15 hex digits", [post + b"Transfer-Encoding: chunked\r\n\r\nfffffffffffffff\r\n"],
              413, code="too_large"),
            R("Content-Length over 1 MiB with the body", [post + b"Content-Length: %d\r\n\r\n" % (MAX_BODY + 1)]
              + [chunk] * over + [b"x"], 413, code="too_large"),
            R("Content-Length 1e30", [post + b"Content-Length: 1000000000000000000000000000000\r\n\r\n"], 413),
            R("Content-Length 2^64", [post + b"Content-Length: 18446744073709551616\r\n\r\n"], 413),
            # (c) Expect: 100-continue with a valid spec of ~20 KB is answered and accepted.
            R("(c) Expect 100-continue, 20 KB spec",
              [post + b"Expect: 100-continue\r\nContent-Length: %d\r\n\r\n" % len(padded), padded], 201,
              continue_wait=1.0, check=continued),
            R("Expect 100-continue, chunked spec",
              [post + b"Expect: 100-continue\r\nTransfer-Encoding: chunked\r\n\r\n", chunked(padded)], 201,
              continue_wait=1.0),
            R("Expect 100-continue over the limit", [post + b"Expect: 100-continue\r\nContent-Length: %d\r\n\r\n"
                                                     % (MAX_BODY + 1)], 413),
            R("Expect something else", [post + b"Expect: 200-ok\r\nContent-Length: 2\r\n\r\n{}"], 417),
            # Chunked framing.
            R("chunked valid spec in 7-byte chunks", [post + b"Transfer-Encoding: chunked\r\n\r\n" + chunked(spec, 7)],
              201),
            R("chunked with extensions and a trailer", [post + b"Transfer-Encoding: chunked\r\n\r\n"
                                                        + b"%x;ext=1\r\n" % len(spec) + spec + b"\r\n0\r\nX-T: 1\r\n\r\n"],
              201),
            R("bad chunk size", [post + b"Transfer-Encoding: chunked\r\n\r\nzz\r\n"], 400),
            R("negative chunk size", [post + b"Transfer-Encoding: chunked\r\n\r\n-1\r\n"], 400),
            R("chunk longer than its size", [post + b"Transfer-Encoding: chunked\r\n\r\n2\r\n{}}}\r\n0\r\n\r\n"], 400),
            R("unknown transfer coding", [post + b"Transfer-Encoding: gzip\r\n\r\n"], 400),
            R("chunked and Content-Length", [post + b"Transfer-Encoding: chunked\r\nContent-Length: 2\r\n\r\n{}"], 400),
            R("Content-Length word", [post + b"Content-Length: many\r\n\r\n"], 400),
            R("Content-Length negative", [post + b"Content-Length: -1\r\n\r\n"], 400),
            R("two different Content-Lengths", [post + b"Content-Length: 2\r\nContent-Length: 3\r\n\r\n{}"], 400),
            R("Content-Length shorter than the body", [post + b"Content-Length: 2\r\n\r\n" + spec], 400,
              code="invalid_json"),
            # Heads and request lines.
            R("head over 16 KiB", [b"GET /v1/health HTTP/1.1\r\nX-Big: " + b"x" * 20000 + b"\r\n\r\n"], 431),
            R("3,000 small headers", [b"GET /v1/health HTTP/1.1\r\n" + b"X-A: b\r\n" * 3000 + b"\r\n"], 431),
            R("request line over 16 KiB", [b"GET /v1/" + b"x" * 17000 + b" HTTP/1.1\r\n\r\n"], (414, 431)),
            R("header without a colon", [b"GET /v1/health HTTP/1.1\r\nnonsense\r\n\r\n"], 400),
            R("header with an empty name", [b"GET /v1/health HTTP/1.1\r\n: x\r\n\r\n"], 400),
            R("space in the path", [b"GET /v1/jobs/1 2 HTTP/1.1\r\n\r\n"], 400),
            R("NUL in the path", [b"GET /v1/jobs/\x00 HTTP/1.1\r\n\r\n"], None),
            R("bare percent in the path", [b"GET /v1/jobs/% HTTP/1.1\r\n\r\n"], None),
            R("absolute-form target", [b"GET http://127.0.0.1/v1/health HTTP/1.1\r\n\r\n"], None),
            R("asterisk target", [b"GET * HTTP/1.1\r\n\r\n"], None),
            R("lower-case method", [b"get /v1/health HTTP/1.1\r\n\r\n"], (400, 404, 405)),
            R("unknown method", [b"FOO /v1/health HTTP/1.1\r\n\r\n"], tuple(range(400, 500))),
            R("HTTP/2.0", [b"GET /v1/health HTTP/2.0\r\n\r\n"], tuple(range(400, 500))),
            R("HTTP/9.9", [b"GET /v1/health HTTP/9.9\r\n\r\n"], tuple(range(400, 500))),
            R("HTTP/1.0 health", [b"GET /v1/health HTTP/1.0\r\n\r\n"], 200),
            R("TLS client hello", [b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03" + b"\x00" * 64 + b"\r\n\r\n"], None,
              no_answer_ok=True),
            R("HTTP/0.9 style", [b"GET /\r\n\r\n"], None, no_answer_ok=True),
            R("only CRLFs then a request", [b"\r\n\r\n\r\nGET /v1/health HTTP/1.1\r\n\r\n"], None, no_answer_ok=True),
        ]

    def test_bad_inputs(self):
        self.elapsed = {}
        counts = {"2xx": 0, "4xx": 0, "5xx": 0, "other": 0, "no answer": 0}
        crashes = []
        done, crystal, n_snapshots = self.fixtures()
        fx = self.sweep_fixtures(crystal)
        status, _, body = self.http("GET", "/v1/experiments")
        self.assertEqual(status, 200, body[:300])
        experiments = json.loads(body)["experiments"]
        self.assertTrue(experiments)
        # The queued cases first: they need the blocker still running.
        cases = (self.queued_cases(fx) + field_cases(experiments) + structure_cases(experiments) + document_cases()
                 + self.route_cases(done, crystal, n_snapshots) + sweep_cases()
                 + self.new_route_cases(done, crystal, n_snapshots, fx) + self.raw_cases(done))
        names = [c.name for c in cases]
        self.assertEqual(len(names), len(set(names)), [n for n in names if names.count(n) > 1][:5])

        for k, case in enumerate(cases, 1):
            with self.subTest(case.name):
                status, headers, body, interim = self.run_case(case)
                bucket = "no answer" if status is None else {2: "2xx", 4: "4xx", 5: "5xx"}.get(status // 100, "other")
                counts[bucket] += 1
                self.cancel_created(case, status, body)
                exit_code = self.proc.poll()
                if exit_code is not None:  # the daemon died on this case: count it, restart, go on
                    crashes.append(case.name)
                    tail = self.log_tail()
                    self.start_daemon()
                    self.fail(f"granulabd died (exit status {exit_code}) on this case; its log ends: {tail}")
                self.judge(case, status, headers, body, interim)
            if k % HEALTH_EVERY == 0:
                with self.subTest(f"alive after case {k}"):
                    self.assertIsNone(self.proc.poll(), "granulabd died")
                    self.assertEqual(self.health_status(), 200, f"GET /v1/health after case {k} ({case.name})")
        with self.subTest("alive at the end"):
            self.assertIsNone(self.proc.poll(), "granulabd died")
            self.assertEqual(self.health_status(), 200)
            status, _, body = self.http("GET", f"/v1/jobs/{done}")
            self.assertEqual(status, 200, "the fixture job is gone")
            self.assertEqual(json.loads(body)["status"], "succeeded")
        slowest = sorted(self.elapsed.items(), key=lambda kv: -kv[1])[:3]
        print(f"\nbad-input suite: {len(cases)} cases, {counts['4xx']} 4xx, {counts['2xx']} 2xx, {counts['5xx']} 5xx, "
              f"{counts['other']} other, {counts['no answer']} without an answer, {len(crashes)} crashes "
              f"(slowest: {', '.join(f'{n} {t:.1f} s' for n, t in slowest)})", file=sys.stderr)
        self.assertGreaterEqual(len(cases), 300)
        self.assertEqual(counts["5xx"], 0, "answers with a 5xx status")
        self.assertEqual(crashes, [], "cases after which granulabd had died")


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main()
