#!/usr/bin/python3
"""OpenAPI conformance: every answer of a real granulabd is checked against the API document the daemon itself
serves at GET /v1/openapi.json (docs/openapi.json with the build's spec schemas).

Three daemons on loopback, each with a real SQLite file in a temporary folder:
- `open`: no token file (everyone is an anonymous admin). A two-cube job, a small crystal compression (its
  snapshots feed the snapshot, picture and export routes) and a sweep are run to the end; then a slow "blocker"
  job runs while jobs and sweeps queue behind it, for the queued and running states (priority, cancel, delete,
  409s), submissions, dry runs and a reuse.
- `users`: --token-file (alice, and boss who is an admin) --private --max-queued-per-user 1: 401 without a token
  or with an unknown one, 403 for alice on boss's jobs and sweeps (reads too, the server being private),
  429 over the queue quota, and what an admin may do.
- `limits`: --max-db-mb 1 on a database already over that size (507), --max-connections 2 (503) and
  --request-timeout 1 (408).

Every operation of the document gets a valid call, an unknown query parameter, bad values of each of its query
parameters, ids that do not exist, and the answers a request can get before it reaches a route (413: a body over
1 MiB, 414: path and query over 8 KiB, 415: a compressed body, 417, 431: a head over 16 KiB). Every answer must:
1. have a status the operation lists (or a `default`/`4XX` response covers);
2. have a Content-Type whose media type that response lists;
3. have a body valid against that media type's schema (JSON Schema 2020-12, $refs resolved in the document).
And every request the server accepted (2xx) must be one the document allows: its path and query parameters
declared and valid against their schemas, its body valid against the request body's schema (so a bound the
document copies from a default, e.g. the largest grain id of the default crystal, is caught by a valid spec
beyond it); every bad query value the server refuses naming a parameter must be refused by that parameter's
schema too (so a bound the document leaves out is caught). The schemas themselves must be valid 2020-12.
All violations are collected, printed at the end grouped by cause with their count, and fail the test.

Run from the repository root:  GRANULABD=build/granulabd /usr/bin/python3 tests/server/openapi_conformance_test.py
(GRANULAB_OPENAPI_DOCUMENT=FILE checks the answers against FILE instead, e.g. an edited docs/openapi.json, before
the daemon is rebuilt with it.)
Standard library and python3-jsonschema (>= 4, for Draft202012Validator); without jsonschema the test says why
and exits with 77 (CTest's SKIP_RETURN_CODE). The daemon binary comes from $GRANULABD or build/granulabd.
"""
import collections
import gzip
import http.client
import json
import os
import re
import select
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.parse

try:
    from jsonschema import Draft202012Validator, RefResolver
    from jsonschema.exceptions import SchemaError
    JSONSCHEMA_PROBLEM = None
except Exception as e:  # ImportError, or a jsonschema older than 4 (no Draft202012Validator)
    JSONSCHEMA_PROBLEM = f"{type(e).__name__}: {e}"

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
SKIP_RETURN_CODE = 77
DOCUMENT_OVERRIDE = "GRANULAB_OPENAPI_DOCUMENT"  # a file to check the answers against instead of the served document

MAX_BODY = 1 << 20     # docs/api.md: bodies up to 1 MiB
MAX_TARGET = 8 << 10   # path and query up to 8 KiB
MAX_HEAD = 16 << 10    # request heads up to 16 KiB
HTTP_TIMEOUT = 15.0
MISSING = 999999999    # an id no job or sweep has

# About a second each on one thread: the fixtures.
TWO = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3}, "loading": {"rate_number": 1e-3},
       "output": {"curve_points": 5}}
CRYSTAL = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
           "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1}, "loading": {"rate_number": 0.1},
           "output": {"curve_points": 4}}
# Minutes of work: it runs while others queue behind it, and is cancelled.
SLOW = {"experiment": "two_cube_sliding", "label": "blocker", "grain": {"edge_spheres": 2},
        "loading": {"rate_number": 1e-7}, "output": {"curve_points": 50}}
# Valid specs whose values lie beyond the defaults a bound could have been copied from: the largest grain id of
# the default 8 x 6 x 18 crystal (863), snapshot strains and program targets above the default max_strain (0.1).
BIG_KNOCKOUT = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
                "crystal": {"grains_x": 10, "rows_z": 10, "layers_y": 9, "knockout": [0, 864, 899]},
                "loading": {"rate_number": 0.1}, "output": {"curve_points": 4}}
HIGH_STRAINS = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
                "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1},
                "loading": {"rate_number": 0.1, "max_strain": 0.3},
                "output": {"curve_points": 4, "snapshot_strains": [0.0, 0.15, 0.3]}}
PROGRAM = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
           "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1},
           "loading": {"rate_number": 0.1, "max_strain": 0.3,
                       "program": [{"to_strain": 0.2}, {"to_deviator": 0}, {"hold_steps": 10}, {"to_strain": 0.25}]},
           "output": {"curve_points": 4}}
ALL_BEYOND = {"experiment": "crystal_compression", "label": "beyond the defaults", "grain": {"edge_spheres": 2},
              "crystal": {"grains_x": 10, "rows_z": 10, "layers_y": 9, "knockout": [899],
                          "knockout_regions": [{"x": 1, "z": -1, "radius": 0.5}]},
              "loading": {"rate_number": 0.1, "max_strain": 0.4, "program": [{"to_strain": 0.35}]},
              "output": {"curve_points": 4, "snapshot_strains": [0.2, 0.35]}}
# The default experiment (two_cube_sliding) left out, or null ("a null value means the field's default").
NO_EXPERIMENT = {"grain": {"edge_spheres": 3}, "loading": {"rate_number": 1e-3}, "output": {"curve_points": 5}}
NULL_EXPERIMENT = dict(NO_EXPERIMENT, experiment=None)
NULL_SECTIONS = {"experiment": "two_cube_sliding", "label": None, "material": None, "run": None,
                 "grain": {"edge_spheres": 3, "size": None}, "loading": {"rate_number": 1e-3},
                 "output": {"curve_points": 5}}
CONFINEMENT = {"experiment": "crystal_confinement", "grain": {"edge_spheres": 2},
               "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1}}
SHEAR = {"experiment": "crystal_shear", "grain": {"edge_spheres": 2},
         "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 3, "layers_y": 1}}
STIFFNESS = {"experiment": "crystal_stiffness", "grain": {"edge_spheres": 2},
             "crystal": {"lattice": "sc", "grains_x": 3, "rows_z": 3, "layers_y": 3}}
TENSION = {"experiment": "crystal_tension", "grain": {"edge_spheres": 2},
           "crystal": {"lattice": "sc", "grains_x": 2, "rows_z": 3, "layers_y": 1},
           "contact": {"normal": "jkr", "surface_energy": 1}, "loading": {"confinement": "none"}}
IMPERFECT = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
             "crystal": {"grains_x": 2, "rows_z": 2, "layers_y": 1},
             "imperfections": {"size_dispersion": 0.05, "misorientation": 5, "seed": 2147483647},
             "loading": {"rate_number": 0.1, "confinement": "fixed_forces", "max_strain": 0.5},
             "output": {"curve_points": 4}}

JSON_TYPE = {"Content-Type": "application/json"}
TOKENS = {"alice": "tok-alice-1234", "boss": "tok-boss-5678"}  # boss is an admin
AS_ALICE = {"Authorization": "Bearer " + TOKENS["alice"]}
AS_BOSS = {"Authorization": "Bearer " + TOKENS["boss"]}
AS_NOBODY = {"Authorization": "Bearer not-a-token"}
WRONG_WORKER = {"X-Worker-Token": "not-the-secret"}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def dumps(doc):
    return json.dumps(doc).encode()


def short(text, n=300):
    text = text if isinstance(text, str) else repr(text)
    return text if len(text) <= n else text[:n] + f"... ({len(text)} characters)"


# -- the daemons ---------------------------------------------------------------------------------------------------
class Answer:
    def __init__(self, status=None, headers=None, body=b"", problem=""):
        self.status, self.headers, self.body, self.problem = status, headers or {}, body, problem

    def json(self):
        try:
            return json.loads(self.body)
        except ValueError:
            return None

    def error_field(self):
        doc = self.json()
        if isinstance(doc, dict) and isinstance(doc.get("error"), dict):
            return doc["error"].get("field")
        return None

    def error_code(self):
        doc = self.json()
        if isinstance(doc, dict) and isinstance(doc.get("error"), dict):
            return doc["error"].get("code")
        return None


def read_answer(sock, timeout):
    """The bytes of one answer read from `sock`: until it is complete, the peer closes, or `timeout` s pass."""
    buf = b""
    deadline = time.time() + timeout
    while time.time() < deadline:
        if not select.select([sock], [], [], max(0.0, deadline - time.time()))[0]:
            break
        try:
            chunk = sock.recv(65536)
        except OSError:
            break
        if not chunk:
            break
        buf += chunk
        got = parse_response(buf)
        if got and got[1]:
            break
    return buf


def parse_response(buf):
    """The final (non-1xx) response in `buf`: an Answer and whether its body is complete, or None."""
    pos = 0
    while True:
        end = buf.find(b"\r\n\r\n", pos)
        if end < 0:
            return None
        lines = buf[pos:end].decode("latin-1").split("\r\n")
        try:
            status = int(lines[0].split(" ", 2)[1])
        except (IndexError, ValueError):
            return Answer(None, {}, buf[pos:], "not an HTTP answer"), True
        headers = {}
        for line in lines[1:]:
            if ":" in line:
                k, v = line.split(":", 1)
                headers[k.strip().lower()] = v.strip()
        if 100 <= status < 200:
            pos = end + 4
            continue
        length = int(headers.get("content-length", "0") or 0)
        body = buf[end + 4:end + 4 + length]
        return Answer(status, headers, body), len(body) == length


class Daemon:
    def __init__(self, name, folder, *options):
        self.name, self.options = name, list(options)
        self.db = os.path.join(folder, name + ".db")
        self.port = free_port()
        self.log = open(os.path.join(folder, name + ".log"), "w+")
        self.proc = None

    def start(self, *extra):
        self.proc = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", self.db, "--workers", "1",
                                      "--threads", "1"] + self.options + list(extra),
                                     stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 20
        while time.time() < deadline and self.proc.poll() is None:
            if self.http("GET", "/v1/health", timeout=1).status == 200:
                return
            time.sleep(0.05)
        raise AssertionError(f"granulabd ({self.name}) did not start ({DAEMON}): {self.log_tail()}")

    def stop(self):
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

    def http(self, method, path, body=None, headers=None, timeout=HTTP_TIMEOUT):
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=timeout)
        try:
            conn.request(method, path, body=body, headers=headers or {})
            r = conn.getresponse()
            data = r.read()
            return Answer(r.status, {k.lower(): v for k, v in r.getheaders()}, data)
        except (OSError, http.client.HTTPException) as e:
            return Answer(None, {}, b"", f"{type(e).__name__}: {e}")
        finally:
            conn.close()

    def raw(self, data, timeout=5.0):
        """Sends `data` on one connection (whatever of it the server takes before it answers), then reads the
        answer: what no HTTP library sends (a head over the limits, an announced body never sent)."""
        buf = b""
        try:
            with socket.create_connection(("127.0.0.1", self.port), timeout=timeout) as s:
                try:
                    s.sendall(data)
                except OSError:
                    pass
                buf = read_answer(s, timeout)
        except OSError as e:
            return Answer(None, {}, b"", f"{type(e).__name__}: {e}")
        got = parse_response(buf)
        return got[0] if got else Answer(None, {}, buf, "no answer")

    def json_of(self, method, path, body=None, headers=None, want=(200, 201)):
        a = self.http(method, path, body, headers)
        if a.status not in want:
            raise AssertionError(f"{self.name}: {method} {path} -> {a.status} {short(a.body)} {a.problem}")
        return a.json()

    def submit(self, spec, query="", headers=None):
        return self.json_of("POST", "/v1/jobs" + query, dumps(spec), dict(JSON_TYPE, **(headers or {})))["id"]

    def status_of(self, job, headers=None):
        return self.json_of("GET", f"/v1/jobs/{job}", headers=headers, want=(200,))["status"]

    def wait(self, jobs, states, headers=None, seconds=60):
        deadline = time.time() + seconds
        for job in jobs:
            while True:
                status = self.status_of(job, headers)
                if status in states:
                    break
                if time.time() > deadline:
                    raise AssertionError(f"{self.name}: job {job} is still {status} after {seconds} s")
                time.sleep(0.02)


def raw_request(method, path, headers=(), body=b""):
    head = f"{method} {path} HTTP/1.1\r\nHost: 127.0.0.1\r\n" + "".join(f"{k}: {v}\r\n" for k, v in headers)
    return head.encode("latin-1") + b"\r\n" + body


# -- the document ----------------------------------------------------------------------------------------------
class Document:
    """The served OpenAPI document: its operations by (METHOD, template), $refs resolved, schemas validated with
    JSON Schema 2020-12 against the whole document."""

    METHODS = ("get", "put", "post", "delete", "patch", "head", "options", "trace")

    def __init__(self, doc):
        self.doc = doc
        self.resolver = RefResolver.from_schema(doc)
        self.validators = {}
        self.ops = {}
        for template, item in doc.get("paths", {}).items():
            item = self.deref(item)
            shared = [self.deref(p) for p in item.get("parameters", [])]
            for method in self.METHODS:
                if method in item:
                    op = self.deref(item[method])
                    params = {(p["name"], p["in"]): p for p in shared}
                    params.update({(p["name"], p["in"]): p for p in map(self.deref, op.get("parameters", []))})
                    self.ops[f"{method.upper()} {template}"] = {"op": op, "template": template,
                                                               "params": params, "regex": self.path_regex(template)}

    @staticmethod
    def path_regex(template):
        out, pos = "", 0
        for m in re.finditer(r"\{([^}/]+)\}", template):
            out += re.escape(template[pos:m.start()]) + f"(?P<{m.group(1)}>[^/]+?)"
            pos = m.end()
        return re.compile("^" + out + re.escape(template[pos:]) + "$")

    def deref(self, obj, depth=0):
        while isinstance(obj, dict) and "$ref" in obj and depth < 20:
            _, obj = self.resolver.resolve(obj["$ref"])
            depth += 1
        return obj

    def errors(self, schema, instance, limit=3):
        """Up to `limit` messages of why `instance` is not valid under `schema` (empty: valid)."""
        key = id(schema)
        if key not in self.validators:
            self.validators[key] = (schema, Draft202012Validator(schema, resolver=self.resolver))
        validator = self.validators[key][1]
        out = []
        for e in sorted(validator.iter_errors(instance), key=lambda e: (len(e.absolute_path), str(e.message)))[:limit]:
            where = "$" + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in e.absolute_path)
            message = e.message
            if e.validator == "oneOf":
                names = ", ".join(s.get("$ref", s.get("title", "{...}")) if isinstance(s, dict) else "?"
                                  for s in e.validator_value)
                message = (f"{short(json.dumps(e.instance), 80)} is valid under "
                           f"{'none' if e.context else 'more than one'} of the oneOf schemas ({names})")
                if e.context:  # the errors of the branch that came closest (the fewest errors)
                    branches = collections.defaultdict(list)
                    for c in e.context:
                        branches[c.relative_schema_path[0]].append(c)
                    depth = len(e.absolute_path)

                    def other_kind(errors):  # a branch for another kind of thing (another experiment's spec)
                        return any(c.validator == "const" or (c.validator == "additionalProperties"
                                                              and len(c.absolute_path) == depth) for c in errors)
                    index, closest = min(branches.items(), key=lambda kv: (other_kind(kv[1]), len(kv[1]), kv[0]))
                    ref = e.validator_value[index].get("$ref", f"branch {index}") if isinstance(
                        e.validator_value[index], dict) else f"branch {index}"
                    message += f"; under {ref}: " + "; ".join(
                        "$" + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in c.absolute_path)
                        + ": " + short(c.message, 120) for c in closest[:3])
            out.append(f"{where}: {short(message, 800)} (schema keyword {e.validator!r} at "
                       f"{'/'.join(str(p) for p in e.absolute_schema_path)})")
        return out

    def response(self, op, status):
        responses = op.get("responses", {})
        for key in (str(status), f"{str(status)[0]}XX", f"{str(status)[0]}xx", "default"):
            if key in responses:
                return key, self.deref(responses[key])
        return None, None

    @staticmethod
    def media_match(media, content):
        if media in content:
            return media
        for key in content:
            k = key.split(";")[0].strip().lower()
            if k == media or k == "*/*" or (k.endswith("/*") and media.startswith(k[:-1])):
                return key
        return None

    def all_schemas(self):
        """(where, schema) of every schema in the document: components and every parameter, body and answer."""
        for name, schema in self.doc.get("components", {}).get("schemas", {}).items():
            yield f"#/components/schemas/{name}", schema

        def walk(node, where):
            if isinstance(node, dict):
                for k, v in node.items():
                    if k == "schema" and isinstance(v, dict):
                        yield f"{where}/schema", v
                    else:
                        yield from walk(v, f"{where}/{k}")
            elif isinstance(node, list):
                for i, v in enumerate(node):
                    yield from walk(v, f"{where}/{i}")
        yield from walk(self.doc.get("paths", {}), "#/paths")


def coerce(value, schema):
    """A query or path value (text) as the JSON value the schema describes (style form, one value)."""
    types = schema.get("type")
    types = [types] if isinstance(types, str) else (types or [])
    if "integer" in types and re.fullmatch(r"-?\d+", value):
        return int(value)
    if "number" in types:
        try:
            return float(value) if not re.fullmatch(r"-?\d+", value) else int(value)
        except ValueError:
            return value
    if "boolean" in types and value in ("true", "false"):
        return value == "true"
    return value


# -- cases -------------------------------------------------------------------------------------------------------
class Case:
    """One request: the operation it exercises ("GET /v1/jobs/{id}"), what is sent, and what it is about.

    expect:     the status (or statuses) docs/api.md says it gets, or None
    bad_param:  a query parameter given a value the server must refuse; a 400 naming it must be refused by the
                parameter's schema too (unless `depends`: a bound that depends on the data, e.g. ?slice=)
    raw:        bytes sent as they are (the head and body limits), instead of method, path, body, headers
    """

    def __init__(self, op, path, body=None, headers=None, expect=None, bad_param=None, depends=False, raw=None,
                 what=""):
        self.op, self.path, self.body = op, path, body
        self.method = op.split(" ", 1)[0]
        self.headers = dict(headers or {})
        if body is not None and "Content-Type" not in self.headers and raw is None:
            self.headers["Content-Type"] = "application/json"
        self.expect = expect if isinstance(expect, tuple) or expect is None else (expect,)
        self.bad_param, self.depends, self.raw, self.what = bad_param, depends, raw, what

    def name(self):
        where = self.path if len(self.path) <= 100 else f"{self.path[:70]}... ({len(self.path)} characters)"
        return f"{self.method} {where}" + (f" [{self.what}]" if self.what else "")


# Every operation, with a concrete path of it (ids filled in by the test) and its query parameters' bad values.
def limit_cases(op, path):
    c = []
    for v in ["0", "1001", "-1", "abc", "1.5", ""]:
        c.append(Case(op, f"{path}?limit={v}", expect=400, bad_param="limit", what="bad limit"))
    for v in ["-1", "abc", str(2 ** 40 + 1)]:
        c.append(Case(op, f"{path}?offset={v}", expect=400, bad_param="offset", what="bad offset"))
    c += [Case(op, f"{path}?limit=1&offset=0", expect=200), Case(op, f"{path}?limit=1000", expect=200),
          Case(op, f"{path}?offset={2 ** 40}", expect=200), Case(op, f"{path}?owner=nobody", expect=200)]
    return c


class OpenApiConformanceTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if JSONSCHEMA_PROBLEM:
            raise unittest.SkipTest(f"python3-jsonschema with Draft202012Validator is needed: {JSONSCHEMA_PROBLEM}")
        if not os.access(DAEMON, os.X_OK):
            raise AssertionError(f"no daemon binary at {DAEMON} (set GRANULABD)")
        cls.dir = tempfile.mkdtemp(prefix="granulab_openapi_")
        tokens = os.path.join(cls.dir, "tokens")
        with open(tokens, "w") as f:
            f.write(f"# user token [admin]\nalice {TOKENS['alice']}\nboss {TOKENS['boss']} admin\n")
        os.chmod(tokens, 0o600)
        cls.open = Daemon("open", cls.dir)
        cls.users = Daemon("users", cls.dir, "--token-file", tokens, "--private", "--max-queued-per-user", "1")
        cls.limits = Daemon("limits", cls.dir, "--max-connections", "2", "--request-timeout", "1")
        cls.daemons = [cls.open, cls.users, cls.limits]
        try:
            cls.open.start()
            cls.users.start()
            # `limits`: its database made, then padded past 1 MB while it is stopped, then served with
            # --max-db-mb 1: the file may not grow, so a new job's or sweep's rows do not fit (507).
            cls.limits.start()
            cls.limits.stop()
            db = sqlite3.connect(cls.limits.db)
            db.execute("CREATE TABLE conformance_padding (x BLOB)")
            db.execute("INSERT INTO conformance_padding VALUES (zeroblob(1200000))")
            db.commit()
            db.close()
            cls.limits.start("--max-db-mb", "1")
        except BaseException:
            cls.tearDownClass()
            raise

    @classmethod
    def tearDownClass(cls):
        for d in getattr(cls, "daemons", []):
            d.stop()
            d.log.close()
        if getattr(cls, "dir", None):
            shutil.rmtree(cls.dir, ignore_errors=True)

    # -- running and judging cases --------------------------------------------------------------------------------
    def violate(self, kind, case, detail, daemon=None):
        self.violations.append({"kind": kind, "op": case.op, "case": case.name(),
                                "daemon": (daemon or self.current).name, "detail": detail})

    def run_cases(self, daemon, cases):
        self.current = daemon
        answers = []
        for case in cases:
            if case.raw is not None:
                answer = daemon.raw(case.raw)
            else:
                answer = daemon.http(case.method, case.path, case.body, case.headers)
            self.requests += 1
            self.per_op[case.op][answer.status] += 1
            self.judge(case, answer)
            answers.append(answer)
            if daemon.proc.poll() is not None:
                raise AssertionError(f"granulabd ({daemon.name}) died on {case.name()}: {daemon.log_tail()}")
        return answers

    def run_one(self, daemon, case):
        return self.run_cases(daemon, [case])[0]

    def judge(self, case, answer):
        entry = self.document.ops.get(case.op)
        if entry is None:
            return self.violate("operation not in the document", case, f"{case.op} is not among its paths")
        op = entry["op"]
        if answer.status is None:
            return self.violate("no answer", case, answer.problem or short(answer.body))
        code = answer.error_code()
        label = f"{answer.status}" + (f" ({code})" if code else "")
        if case.expect is not None and answer.status not in case.expect:
            self.violate("unexpected status", case,
                         f"got {label}, docs/api.md says {case.expect}: {short(answer.body, 200)}")
        # 1. The status.
        key, response = self.document.response(op, answer.status)
        if response is None:
            self.violate(f"status {answer.status} not documented", case,
                         f"{label} is not among the responses {sorted(op.get('responses', {}))}")
        else:
            self.judge_body(case, answer, key, response)
        # The request, when the server took it.
        if 200 <= answer.status < 300 and case.raw is None:
            self.judge_request(case, entry)
        if case.bad_param and answer.status == 400 and answer.error_field() == case.bad_param and not case.depends:
            self.judge_refused_param(case, entry)

    def judge_body(self, case, answer, key, response):
        content = response.get("content") or {}
        body = answer.body
        ctype = answer.headers.get("content-type", "")
        media = ctype.split(";")[0].strip().lower()
        if not content:
            if body:
                self.violate("body not documented", case, f"{answer.status} documents no content, got {media or 'no type'} "
                                                          f"({len(body)} bytes)")
            return
        # 2. The media type.
        listed = self.document.media_match(media, content)
        if listed is None:
            return self.violate("media type not documented", case,
                                f"{answer.status} answered {ctype or '(no Content-Type)'}; response {key!r} lists "
                                f"{list(content)}")
        schema = self.document.deref(content[listed]).get("schema")
        if schema is None:
            return
        # 3. The body against the schema.
        if media == "application/json" or media.endswith("+json"):
            try:
                instance = json.loads(body)
            except ValueError as e:
                return self.violate("body does not match its media type", case, f"{media} that is not JSON: {e}: "
                                                                              f"{short(body, 120)}")
        elif schema.get("format") == "binary" or schema.get("contentMediaType") or schema.get("contentEncoding"):
            instance = body.decode("latin-1")
        else:
            try:
                instance = body.decode("utf-8")
            except UnicodeDecodeError as e:
                return self.violate("body does not match its media type", case, f"{media} that is not UTF-8 text: {e}")
        for message in self.document.errors(schema, instance):
            self.violate("body does not match the schema", case, f"{answer.status} {media}: {message}")

    def judge_request(self, case, entry):
        """A request the server accepted must be one the document allows."""
        url = urllib.parse.urlsplit(case.path)
        m = entry["regex"].match(url.path)
        if not m:
            return self.violate("test error: path does not match its template", case, entry["template"])
        params = entry["params"]
        for name, value in m.groupdict().items():
            p = params.get((name, "path"))
            if p is None:
                self.violate("path parameter not documented", case, name)
            elif "schema" in p:
                for message in self.document.errors(p["schema"], coerce(urllib.parse.unquote(value), p["schema"])):
                    self.violate("accepted a path value the document forbids", case, f"{name}={value}: {message}")
        query = urllib.parse.parse_qsl(url.query, keep_blank_values=True)
        for name, value in query:
            p = params.get((name, "query"))
            if p is None:
                if not entry["op"].get("x-ignores-query", False):
                    self.violate("accepted an undocumented query parameter", case, name)
            elif "schema" in p:
                for message in self.document.errors(p["schema"], coerce(value, p["schema"])):
                    self.violate("accepted a query value the document forbids", case, f"{name}={value!r}: {message}")
        given = {name for name, _ in query}
        for (name, where), p in params.items():
            if where == "query" and p.get("required") and name not in given:
                self.violate("accepted without a required parameter", case, name)
        body_spec = self.document.deref(entry["op"].get("requestBody")) or {}
        if not body_spec:
            return
        content = body_spec.get("content", {})
        sent = (case.body or b"")
        if not sent:
            if body_spec.get("required"):
                self.violate("accepted without its required body", case, "")
            return
        media = case.headers.get("Content-Type", "application/octet-stream").split(";")[0].strip().lower()
        listed = self.document.media_match(media, content)
        if listed is None:
            return self.violate("accepted a body of an undocumented media type", case, f"{media}; lists {list(content)}")
        schema = self.document.deref(content[listed]).get("schema")
        if schema is None:
            return
        instance = json.loads(sent) if media == "application/json" else sent.decode("latin-1")
        for message in self.document.errors(schema, instance):
            self.violate("the request schema refuses a body the server accepted", case, message)

    def judge_refused_param(self, case, entry):
        """The server refused this query value naming its parameter: the document must refuse it too."""
        p = entry["params"].get((case.bad_param, "query"))
        query = urllib.parse.parse_qsl(urllib.parse.urlsplit(case.path).query, keep_blank_values=True)
        values = [v for k, v in query if k == case.bad_param]
        if p is None:
            return self.violate("refused parameter not documented", case, case.bad_param)
        if values and "schema" in p and not self.document.errors(p["schema"], coerce(values[-1], p["schema"])):
            self.violate("the document allows a value the server refuses", case,
                         f"{case.bad_param}={values[-1]!r} is valid under {json.dumps(p['schema'])}")

    # -- the cases of each daemon -----------------------------------------------------------------------------
    def transport_cases(self, op, path, body=None, content_type="application/json"):
        """What any request can get before it reaches a route: 414, 431, and for a POST 413 and 415."""
        method = op.split(" ", 1)[0]
        sep = "&" if "?" in path else "?"
        long_path = path + sep + "pad=" + "x" * (MAX_TARGET + 100)
        cases = [Case(op, long_path, body, {"Content-Type": content_type} if body is not None else {}, expect=414,
                      what="path and query over 8 KiB"),
                 Case(op, path, raw=raw_request(method, path, [("X-Big", "x" * (MAX_HEAD + 1000))]), expect=431,
                      what="head over 16 KiB")]
        if method == "POST":
            cases.append(Case(op, path, raw=raw_request(method, path, [("Content-Type", content_type),
                                                                       ("Content-Length", str(MAX_BODY + 1))]),
                              expect=413, what="Content-Length over 1 MiB"))
            packed = gzip.compress(body or b"{}")
            cases.append(Case(op, path, raw=raw_request(method, path, [("Content-Type", content_type),
                                                                       ("Content-Encoding", "gzip"),
                                                                       ("Content-Length", str(len(packed)))], packed),
                              expect=415, what="gzip body"))
        return cases

    def finished_cases(self, f):
        """On `open`, the jobs and the sweep finished: every read route, its bad values, ids that are not."""
        d, c, s = f["two"], f["crystal"], f["sweep"]
        sj = f["sweep_jobs"][0]
        G = lambda op, path, **kw: Case(op, path, **kw)
        cases = []
        # The page, its files, the meta routes.
        for op, path in [("GET /", "/"), ("GET /web/app.js", "/web/app.js"), ("GET /web/style.css", "/web/style.css"),
                         ("GET /v1/health", "/v1/health"), ("GET /v1/openapi.json", "/v1/openapi.json"),
                         ("GET /v1/experiments", "/v1/experiments"), ("GET /v1/examples", "/v1/examples")]:
            # The page's files ignore any query (x-ignores-query: a browser's cache-busting ?v=2); the API refuses one.
            ignores = self.document.ops[op]["op"].get("x-ignores-query", False)
            cases += [G(op, path, expect=200), G(op, path + "?junk=1", expect=200 if ignores else 400,
                                                  what="a query the file ignores" if ignores else "unknown parameter")]
            cases += self.transport_cases(op, path)
        cases.append(Case("GET /v1/health", "/v1/health", raw=b"GET /v1/health HTTP/1.1\r\nnonsense\r\n\r\n",
                          expect=400, what="a header line without a colon"))
        cases.append(Case("GET /v1/jobs/{id}", f"/v1/jobs/{d}",
                          raw=f"GET /v1/jobs/{d} HTTP/1.1\r\n folded: x\r\n\r\n".encode(), expect=400,
                          what="a folded header line"))
        # GET /v1/jobs.
        op = "GET /v1/jobs"
        cases += [G(op, "/v1/jobs", expect=200)] + limit_cases(op, "/v1/jobs")
        for v in ["queued", "running", "succeeded", "failed", "cancelled"]:
            cases.append(G(op, f"/v1/jobs?status={v}", expect=200))
        for v in ["bogus", "QUEUED", "succeeded,failed"]:
            cases.append(G(op, f"/v1/jobs?status={v}", expect=400, bad_param="status", what="bad status"))
        cases += [G(op, "/v1/jobs?junk=1", expect=400, what="unknown parameter"),
                  G(op, "/v1/jobs?resue=true", expect=400, what="unknown parameter")]
        cases += self.transport_cases(op, "/v1/jobs")
        cases.append(Case(op, "/v1/jobs", raw=raw_request("GET", "/v1/jobs", [("Content-Length", str(MAX_BODY + 1))]),
                          expect=413, what="GET announcing a body over 1 MiB"))
        # One job.
        for job in (d, c, sj):
            cases.append(G("GET /v1/jobs/{id}", f"/v1/jobs/{job}", expect=200))
        for path_op, tail, ok in [("GET /v1/jobs/{id}", "", True), ("GET /v1/jobs/{id}/curve", "/curve", True),
                                  ("GET /v1/jobs/{id}/curve.svg", "/curve.svg", True),
                                  ("GET /v1/jobs/{id}/snapshots", "/snapshots", True),
                                  ("GET /v1/jobs/{id}/archive", "/archive", True),
                                  ("DELETE /v1/jobs/{id}", "", False),
                                  ("POST /v1/jobs/{id}/cancel", "/cancel", False),
                                  ("POST /v1/jobs/{id}/priority", "/priority?value=1", False),
                                  ("GET /v1/jobs/{id}/snapshots/{k}", "/snapshots/0", True),
                                  ("GET /v1/jobs/{id}/snapshots/{k}.svg", "/snapshots/0.svg", True),
                                  ("GET /v1/jobs/{id}/snapshots/{k}/dic.svg", "/snapshots/0/dic.svg", True)]:
            body = b"" if path_op.startswith("POST") else None
            for bad in [str(MISSING), "0", "9" * 25]:
                cases.append(G(path_op, f"/v1/jobs/{bad}{tail}", body=body, expect=404, what="no such job"))
            cases.append(G(path_op, f"/v1/jobs/abc{tail}", body=body, expect=404, what="an id that is no number"))
            target = c if "snapshots/" in tail else d
            if path_op != "DELETE /v1/jobs/{id}":  # never the fixtures: a junk parameter is refused first, but still
                sep = "&" if "?" in tail else "?"
                cases.append(G(path_op, f"/v1/jobs/{target}{tail}{sep}junk=1", body=body, expect=400,
                               what="unknown parameter"))
                cases += self.transport_cases(path_op, f"/v1/jobs/{target}{tail}", body)
        cases.append(G("DELETE /v1/jobs/{id}", f"/v1/jobs/{MISSING}?junk=1", expect=400, what="unknown parameter"))
        cases += self.transport_cases("DELETE /v1/jobs/{id}", f"/v1/jobs/{MISSING}")
        # Cancel and priority of finished jobs: 409.
        cases += [G("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{d}/cancel", body=b"", expect=409),
                  G("POST /v1/jobs/{id}/priority", f"/v1/jobs/{d}/priority?value=5", body=b"", expect=409)]
        for v in ["", "abc", "101", "-101", "1.5"]:
            cases.append(G("POST /v1/jobs/{id}/priority", f"/v1/jobs/{d}/priority?value={v}", body=b"", expect=400,
                           bad_param="value", what="bad value"))
        cases.append(G("POST /v1/jobs/{id}/priority", f"/v1/jobs/{d}/priority", body=b"", expect=400,
                       what="no value"))
        # Curves.
        op = "GET /v1/jobs/{id}/curve"
        for job in (d, c):
            cases += [G(op, f"/v1/jobs/{job}/curve", expect=200), G(op, f"/v1/jobs/{job}/curve?format=json", expect=200),
                      G(op, f"/v1/jobs/{job}/curve?format=csv", expect=200)]
        for v in ["xml", "CSV", ""]:
            cases.append(G(op, f"/v1/jobs/{d}/curve?format={v}", expect=400, bad_param="format", what="bad format"))
        for job in (d, c, sj):
            cases.append(G("GET /v1/jobs/{id}/curve.svg", f"/v1/jobs/{job}/curve.svg", expect=200))
        # Snapshots: the list, each one in each format, the pictures.
        cases += [G("GET /v1/jobs/{id}/snapshots", f"/v1/jobs/{c}/snapshots", expect=200),
                  G("GET /v1/jobs/{id}/snapshots", f"/v1/jobs/{d}/snapshots", expect=200)]
        op = "GET /v1/jobs/{id}/snapshots/{k}"
        for k in range(min(2, f["snapshots"])):
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}", expect=200))
            for fmt in ["json", "dump", "dump_spheres", "vtk", "vtk_interfaces", "contacts_vtk", "contacts_dump", "mesh_vtk", "dic_csv",
                        "dic_vtk"]:
                cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}?format={fmt}", expect=200))
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}?format=dic_csv&step=0.002", expect=200))
        for v in ["0", "-1", "abc", "2"]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0?format=dic_vtk&step={v}", expect=400, bad_param="step",
                           what="bad grid step"))
        cases.append(G(op, f"/v1/jobs/{c}/snapshots/0?format=dic_vtk&step=1e-9", expect=400, bad_param="step",
                       depends=True, what="a grid over 250,000 nodes"))
        for v in ["xml", "csv", "VTK", ""]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0?format={v}", expect=400, bad_param="format", what="bad format"))
        for k in [str(f["snapshots"]), "9" * 25]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}", expect=404, what="no such snapshot"))
        cases.append(G(op, f"/v1/jobs/{d}/snapshots/0", expect=404, what="two cubes take no snapshot"))
        op = "GET /v1/jobs/{id}/snapshots/{k}.svg"
        cases.append(G(op, f"/v1/jobs/{c}/snapshots/0.svg", expect=200))
        for field in ["penetration_ratio", "gamma_max", "equivalent_strain", "displacement"]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/1.svg?field={field}&slice=0", expect=200))
        for v in ["bogus", "Severity", ""]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0.svg?field={v}", expect=400, bad_param="field",
                           what="bad field"))
        for v in ["-1", "abc", "1.5"]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0.svg?slice={v}", expect=400, bad_param="slice",
                           what="bad slice"))
        cases.append(G(op, f"/v1/jobs/{c}/snapshots/0.svg?slice=999", expect=400, bad_param="slice", depends=True,
                       what="a layer outside the crystal"))
        for k in [str(f["snapshots"]), "9" * 25]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}.svg", expect=404, what="no such snapshot"))
        cases.append(G(op, f"/v1/jobs/{d}/snapshots/0.svg", expect=404, what="two cubes take no snapshot"))
        op = "GET /v1/jobs/{id}/snapshots/{k}/dic.svg"
        cases.append(G(op, f"/v1/jobs/{c}/snapshots/0/dic.svg", expect=200))
        for field in ["gamma_max", "exx", "ezz", "exz", "ux", "uz"]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/1/dic.svg?field={field}&step=0.003", expect=200))
        for v in ["bogus", "severity", ""]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0/dic.svg?field={v}", expect=400, bad_param="field",
                           what="bad field"))
        for v in ["0", "-0.5", "x"]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/0/dic.svg?step={v}", expect=400, bad_param="step",
                           what="bad grid step"))
        cases.append(G(op, f"/v1/jobs/{c}/snapshots/0/dic.svg?step=1e-9", expect=400, bad_param="step", depends=True,
                       what="a grid over 250,000 nodes"))
        for k in [str(f["snapshots"]), "9" * 25]:
            cases.append(G(op, f"/v1/jobs/{c}/snapshots/{k}/dic.svg", expect=404, what="no such snapshot"))
        cases.append(G(op, f"/v1/jobs/{d}/snapshots/0/dic.svg", expect=404, what="two cubes take no snapshot"))
        # Archives.
        for job in (d, c):
            cases.append(G("GET /v1/jobs/{id}/archive", f"/v1/jobs/{job}/archive", expect=200))
        # Sweeps.
        op = "GET /v1/sweeps"
        cases += [G(op, "/v1/sweeps", expect=200)] + limit_cases(op, "/v1/sweeps")
        cases += [G(op, "/v1/sweeps?status=succeeded", expect=400, what="unknown parameter")]
        cases += self.transport_cases(op, "/v1/sweeps")
        for sop, tail in [("GET /v1/sweeps/{id}", ""), ("GET /v1/sweeps/{id}/curves.svg", "/curves.svg"),
                          ("POST /v1/sweeps/{id}/cancel", "/cancel")]:
            body = b"" if sop.startswith("POST") else None
            cases.append(G(sop, f"/v1/sweeps/{s}{tail}", body=body, expect=200))
            for bad in [str(MISSING), "0", "9" * 25, "abc"]:
                cases.append(G(sop, f"/v1/sweeps/{bad}{tail}", body=body, expect=404, what="no such sweep"))
            cases.append(G(sop, f"/v1/sweeps/{s}{tail}?junk=1", body=body, expect=400, what="unknown parameter"))
            cases += self.transport_cases(sop, f"/v1/sweeps/{s}{tail}", body)
        # The workers' routes: no job of a local daemon has a worker, so every secret is wrong (403), and an
        # unknown job answers the same.
        worker = [("GET /v1/worker/jobs/{id}", "", None, "application/json"),
                  ("GET /v1/worker/jobs/{id}/checkpoint", "/checkpoint", None, "application/json"),
                  ("GET /v1/worker/jobs/{id}/checkpoint/{generation}/{index}", "/checkpoint/1/0", None,
                   "application/octet-stream"),
                  ("POST /v1/worker/jobs/{id}/checkpoint/begin", "/checkpoint/begin", b"", "application/json"),
                  ("POST /v1/worker/jobs/{id}/checkpoint/{generation}/{index}", "/checkpoint/1/0", b"\x00chunk",
                   "application/octet-stream"),
                  ("POST /v1/worker/jobs/{id}/checkpoint",
                   "/checkpoint?generation=1&chunks=1&bytes=1&rows=0&snapshots=0&engine_version=x", b"",
                   "application/octet-stream"),
                  ("POST /v1/worker/jobs/{id}/begin", "/begin", dumps({"header": "a,b\n"}), "application/json"),
                  ("POST /v1/worker/jobs/{id}/results", "/results",
                   dumps({"first_index": 0, "lines": ["1,2\n"], "snapshots": [], "progress": 0.5}), "application/json"),
                  ("POST /v1/worker/jobs/{id}/end", "/end", dumps({"outcome": "failed", "error": "x"}),
                   "application/json")]
        for wop, tail, body, ctype in worker:
            h = {"Content-Type": ctype} if body is not None else {}
            cases += [G(wop, f"/v1/worker/jobs/{d}{tail}", body=body, headers=dict(h, **WRONG_WORKER), expect=403,
                        what="a wrong worker secret"),
                      G(wop, f"/v1/worker/jobs/{d}{tail}", body=body, headers=h, expect=403, what="no worker secret"),
                      G(wop, f"/v1/worker/jobs/{MISSING}{tail}", body=body, headers=dict(h, **WRONG_WORKER),
                        expect=403, what="no such job"),
                      G(wop, f"/v1/worker/jobs/{d}{tail}{'&' if '?' in tail else '?'}junk=1", body=body,
                        headers=dict(h, **WRONG_WORKER), expect=400, what="unknown parameter")]
            if wop.startswith("GET /v1/worker/jobs/{id}") and tail == "":
                cases.append(G(wop, f"/v1/worker/jobs/{d}?engine_version=0.0", headers=WRONG_WORKER, expect=403))
            if wop == "POST /v1/worker/jobs/{id}/checkpoint":
                for q in ["generation=1&chunks=1&bytes=1&rows=-1&snapshots=0",
                          "generation=1&chunks=1&bytes=1&rows=abc&snapshots=0"]:
                    cases.append(G(wop, f"/v1/worker/jobs/{d}/checkpoint?{q}", body=body, headers=dict(h, **WRONG_WORKER),
                                   expect=403, what="bad rows, checked after the secret"))
            cases += self.transport_cases(wop, f"/v1/worker/jobs/{d}{tail}", body, ctype)
        return cases

    def submission_cases(self, f):
        """On `open` while the blocker runs: submissions (each queued behind it), dry runs, a reuse, sweeps."""
        cases = []
        op = "POST /v1/jobs"
        P = lambda query, spec, **kw: Case(op, "/v1/jobs" + query, spec if isinstance(spec, bytes) else dumps(spec), **kw)
        cases += [P("", dict(TWO, label="submitted"), expect=201),
                  P("?priority=-100", dict(TWO, label="low"), expect=201),
                  P("?priority=100&reuse=false&dry_run=false", dict(TWO, label="high"), expect=201),
                  P("?reuse=true", TWO, expect=200, what="the same spec as a succeeded job"),
                  P("?reuse=true", dict(TWO, label="another label"), expect=200, what="the label aside"),
                  P("?dry_run=true", TWO, expect=200), P("?dry_run=true&priority=3", CRYSTAL, expect=200)]
        for name, spec in [("knockout ids beyond the default crystal's", BIG_KNOCKOUT),
                           ("snapshot strains beyond the default max_strain", HIGH_STRAINS),
                           ("a program beyond the default max_strain", PROGRAM),
                           ("all of those", ALL_BEYOND), ("the default experiment left out", NO_EXPERIMENT),
                           ("experiment null (the default)", NULL_EXPERIMENT), ("sections null", NULL_SECTIONS),
                           ("crystal_confinement", CONFINEMENT), ("crystal_shear", SHEAR),
                           ("crystal_stiffness", STIFFNESS), ("crystal_tension", TENSION),
                           ("imperfections at their bounds", IMPERFECT)]:
            cases.append(P("?dry_run=true", spec, expect=200, what=name))
        cases += [P("?dry_run=true", dict(CRYSTAL, crystal={"grains_x": 100, "rows_z": 400, "layers_y": 10}), expect=200,
                    what="over budget: the 400's message in the estimate")]
        for q, param in [("priority=high", "priority"), ("priority=101", "priority"), ("priority=-101", "priority"),
                         ("priority=1.5", "priority"), ("priority=", "priority"), ("reuse=yes", "reuse"),
                         ("reuse=", "reuse"), ("dry_run=maybe", "dry_run"), ("dry_run=1", "dry_run")]:
            cases.append(P("?" + q, TWO, expect=400, bad_param=param, what="bad " + param))
        cases += [P("?junk=1", TWO, expect=400, what="unknown parameter"),
                  P("?resue=true", TWO, expect=400, what="unknown parameter"),
                  P("", b"", expect=400, what="empty body"), P("", b"{", expect=400, what="not JSON"),
                  P("", b"[]", expect=400, what="not an object"),
                  P("", dict(TWO, bogus=1), expect=400, what="unknown field"),
                  P("", {"experiment": "nope"}, expect=400, what="unknown experiment"),
                  P("", dict(TWO, grain={"edge_spheres": 1}), expect=400, what="below the minimum"),
                  P("", dict(CRYSTAL, crystal={"grains_x": 2, "rows_z": 2, "layers_y": 1, "knockout": [4]}),
                    expect=400, what="a grain id beyond this crystal"),
                  P("", dict(CRYSTAL, output={"snapshot_strains": [0.2]}), expect=400,
                    what="a snapshot strain beyond this max_strain"),
                  P("", b'{"label": "a", "label": "b"}', expect=400, what="duplicate field"),
                  P("", b"[" * 100 + b"]" * 100, expect=400, what="too deep"),
                  P("", dict(CRYSTAL, crystal={"grains_x": 100, "rows_z": 400, "layers_y": 10},
                             loading={"rate_number": 1e-8}), expect=400, what="over budget"),
                  Case(op, "/v1/jobs", raw=raw_request("POST", "/v1/jobs", [("Content-Type", "application/json"),
                                                                            ("Expect", "200-ok"),
                                                                            ("Content-Length", "2")], b"{}"),
                       expect=417, what="an Expect other than 100-continue")]
        cases += self.transport_cases(op, "/v1/jobs", dumps(TWO))
        # Sweeps.
        op = "POST /v1/sweeps"
        S = lambda query, doc, **kw: Case(op, "/v1/sweeps" + query, doc if isinstance(doc, bytes) else dumps(doc), **kw)
        ok = {"spec": TWO, "vary": {"output.curve_points": [3, 4]}}
        cases += [S("", ok, expect=201), S("?priority=-100", dict(ok, mode="zip", label="zip"), expect=201),
                  S("", {"spec": NO_EXPERIMENT, "vary": {"loading.rate_number": [1e-3, 2e-3]}}, expect=201,
                    what="a base spec without experiment"),
                  S("", {"spec": BIG_KNOCKOUT, "vary": {"crystal.knockout": [[1], [898]]}, "label": "knockouts"},
                    expect=201, what="a base spec beyond the defaults"),
                  # tests/server/bad_input_test.py: a field of the base that vary sets need not be valid in the base.
                  S("", {"spec": dict(TWO, grain={"edge_spheres": 1}), "vary": {"grain.edge_spheres": [2, 3]}},
                    expect=201, what="a base spec valid only once vary has set its keys")]
        for q in ["priority=high", "priority=101", "priority="]:
            cases.append(S("?" + q, ok, expect=400, bad_param="priority", what="bad priority"))
        cases += [S("?dry_run=true", ok, expect=400, what="unknown parameter"),
                  S("", b"{", expect=400, what="not JSON"), S("", {"spec": TWO}, expect=400, what="no vary"),
                  S("", {"vary": ok["vary"]}, expect=400, what="no spec"),
                  S("", dict(ok, vary={"grain.bogus": [1]}), expect=400, what="unknown vary key"),
                  S("", dict(ok, vary={"output.curve_points": [0]}), expect=400, what="a bad value"),
                  S("", dict(ok, mode="cartesian"), expect=400, what="bad mode"),
                  S("", dict(ok, bogus=1), expect=400, what="unknown key"),
                  S("", dict(ok, vary={"output.curve_points": list(range(1, 1002))}), expect=400,
                    what="over 1000 jobs")]
        cases += self.transport_cases(op, "/v1/sweeps", dumps(ok))
        return cases

    def created(self, answers, cases, route):
        out = []
        for case, a in zip(cases, answers):
            if case.op == f"POST {route}" and a.status == 201:
                out.append(a.json()["id"])
        return out

    # -- the test -------------------------------------------------------------------------------------------------
    def test_every_answer_conforms_to_the_served_document(self):
        started = time.time()
        self.violations, self.requests = [], 0
        self.per_op = collections.defaultdict(collections.Counter)
        o, u, lim = self.open, self.users, self.limits
        self.current = o

        # The document, and its schemas as schemas.
        served = o.http("GET", "/v1/openapi.json")
        self.assertEqual(served.status, 200, short(served.body))
        doc = served.json()
        self.assertIsInstance(doc, dict, "GET /v1/openapi.json is not a JSON object")
        if os.environ.get(DOCUMENT_OVERRIDE):  # to try a changed document against the same daemon
            with open(os.environ[DOCUMENT_OVERRIDE]) as f:
                doc = json.load(f)
            print(f"\nchecking against {os.environ[DOCUMENT_OVERRIDE]} ({DOCUMENT_OVERRIDE}), not the served document",
                  file=sys.stderr)
        self.assertTrue(str(doc.get("openapi", "")).startswith("3.1"), f"openapi {doc.get('openapi')!r}")
        self.document = Document(doc)
        self.assertGreaterEqual(len(self.document.ops), 25, sorted(self.document.ops))
        for where, schema in self.document.all_schemas():
            try:
                Draft202012Validator.check_schema(schema)
            except SchemaError as e:
                self.violations.append({"kind": "invalid schema", "op": where, "case": where, "daemon": o.name,
                                        "detail": short(e.message)})

        # -- `open`: fixtures run to the end --------------------------------------------------------------------
        f = {"two": o.submit(TWO), "crystal": o.submit(CRYSTAL)}
        sweep = o.json_of("POST", "/v1/sweeps", dumps({"spec": TWO, "label": "fixture sweep",
                                                       "vary": {"output.curve_points": [4, 6]}}), JSON_TYPE)
        f["sweep"], f["sweep_jobs"] = sweep["id"], sweep["jobs"]
        o.wait([f["two"], f["crystal"]] + f["sweep_jobs"], ("succeeded",))
        f["snapshots"] = len(o.json_of("GET", f"/v1/jobs/{f['crystal']}/snapshots")["snapshots"])
        self.assertGreaterEqual(f["snapshots"], 2, "the crystal fixture took fewer than 2 snapshots")
        self.run_cases(o, self.finished_cases(f))

        # -- `open`: a blocker runs, jobs and sweeps queue behind it ---------------------------------------------
        blocker = o.submit(SLOW, "?priority=100")
        o.wait([blocker], ("running",))
        queued = o.submit(dict(TWO, label="queued"), "?priority=-100")
        doomed = o.submit(dict(TWO, label="cancelled, then deleted"), "?priority=-100")
        beyond = o.submit(ALL_BEYOND, "?priority=-100")  # its stored spec is read back below
        q_sweep = o.json_of("POST", "/v1/sweeps?priority=-100",
                            dumps({"spec": TWO, "vary": {"label": ["q1", "q2"]}}), JSON_TYPE)["id"]
        time.sleep(1.2)  # the blocker's first rows are stored every second: its live curve and `latest`
        J = lambda op, path, **kw: Case(op, path, **kw)
        state_cases = [
            J("GET /v1/jobs/{id}", f"/v1/jobs/{blocker}", expect=200, what="running"),
            J("GET /v1/jobs/{id}", f"/v1/jobs/{queued}", expect=200, what="queued"),
            J("GET /v1/jobs/{id}", f"/v1/jobs/{beyond}", expect=200, what="a spec beyond the defaults"),
            J("GET /v1/jobs", "/v1/jobs?status=running", expect=200),
            J("GET /v1/jobs", "/v1/jobs?status=queued&limit=2", expect=200),
            J("GET /v1/jobs/{id}/curve", f"/v1/jobs/{blocker}/curve", expect=(200, 409), what="running"),
            J("GET /v1/jobs/{id}/curve", f"/v1/jobs/{blocker}/curve?format=csv", expect=(200, 409), what="running"),
            J("GET /v1/jobs/{id}/curve.svg", f"/v1/jobs/{blocker}/curve.svg", expect=(200, 409), what="running"),
            J("GET /v1/jobs/{id}/curve", f"/v1/jobs/{queued}/curve", expect=409, what="queued"),
            J("GET /v1/jobs/{id}/curve", f"/v1/jobs/{queued}/curve?format=csv", expect=409, what="queued"),
            J("GET /v1/jobs/{id}/curve.svg", f"/v1/jobs/{queued}/curve.svg", expect=409, what="queued"),
            J("GET /v1/jobs/{id}/snapshots", f"/v1/jobs/{queued}/snapshots", expect=200, what="queued"),
            J("GET /v1/jobs/{id}/snapshots/{k}", f"/v1/jobs/{queued}/snapshots/0", expect=404, what="queued"),
            J("GET /v1/jobs/{id}/snapshots/{k}.svg", f"/v1/jobs/{queued}/snapshots/0.svg", expect=404, what="queued"),
            J("GET /v1/jobs/{id}/archive", f"/v1/jobs/{queued}/archive", expect=200, what="queued"),
            J("GET /v1/jobs/{id}/archive", f"/v1/jobs/{blocker}/archive", expect=200, what="running"),
            J("GET /v1/sweeps/{id}", f"/v1/sweeps/{q_sweep}", expect=200, what="queued"),
            J("GET /v1/sweeps/{id}/curves.svg", f"/v1/sweeps/{q_sweep}/curves.svg", expect=200, what="queued"),
            J("POST /v1/jobs/{id}/priority", f"/v1/jobs/{queued}/priority?value=-50", body=b"", expect=200),
            J("POST /v1/jobs/{id}/priority", f"/v1/jobs/{queued}/priority?value=100", body=b"", expect=200),
            J("POST /v1/jobs/{id}/priority", f"/v1/jobs/{blocker}/priority?value=1", body=b"", expect=409,
              what="running"),
            J("DELETE /v1/jobs/{id}", f"/v1/jobs/{queued}", expect=409, what="queued"),
            J("DELETE /v1/jobs/{id}", f"/v1/jobs/{blocker}", expect=409, what="running"),
            J("DELETE /v1/jobs/{id}", f"/v1/jobs/{doomed}?junk=1", expect=400, what="unknown parameter"),
            J("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{doomed}/cancel", body=b"", expect=200, what="queued"),
            J("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{doomed}/cancel", body=b"", expect=409, what="cancelled"),
            J("GET /v1/jobs/{id}/curve", f"/v1/jobs/{doomed}/curve", expect=409, what="cancelled before it ran"),
            J("GET /v1/jobs/{id}/archive", f"/v1/jobs/{doomed}/archive", expect=200, what="cancelled"),
            J("DELETE /v1/jobs/{id}", f"/v1/jobs/{doomed}", expect=200, what="cancelled"),
            J("DELETE /v1/jobs/{id}", f"/v1/jobs/{doomed}", expect=404, what="deleted"),
            J("GET /v1/jobs/{id}", f"/v1/jobs/{doomed}", expect=404, what="deleted"),
        ]
        self.run_cases(o, state_cases)
        subs = self.submission_cases(f)
        answers = self.run_cases(o, subs)
        new_jobs, new_sweeps = self.created(answers, subs, "/v1/jobs"), self.created(answers, subs, "/v1/sweeps")
        sweep_reads = []
        for s in new_sweeps:
            sweep_reads += [J("GET /v1/sweeps/{id}", f"/v1/sweeps/{s}", expect=200),
                            J("GET /v1/sweeps/{id}/curves.svg", f"/v1/sweeps/{s}/curves.svg", expect=200)]
        sweep_reads += [J("GET /v1/sweeps", "/v1/sweeps?limit=3", expect=200)]
        sweep_reads += [J("GET /v1/jobs/{id}", f"/v1/jobs/{j}", expect=200) for j in new_jobs[:2]]
        self.run_cases(o, sweep_reads)
        # Everything queued is cancelled, then the blocker (202: it stops within a second).
        cleanup = [J("POST /v1/sweeps/{id}/cancel", f"/v1/sweeps/{s}/cancel", body=b"", expect=200)
                   for s in new_sweeps + [q_sweep]]
        cleanup += [J("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{j}/cancel", body=b"", expect=200)
                    for j in new_jobs + [queued, beyond]]
        cleanup += [J("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{blocker}/cancel", body=b"", expect=202)]
        self.run_cases(o, cleanup)

        # -- `users`: tokens, owners, the quota -----------------------------------------------------------------
        ub = u.submit(SLOW, headers=AS_BOSS)
        u.wait([ub], ("running",), headers=AS_BOSS)
        bs = u.json_of("POST", "/v1/sweeps", dumps({"spec": TWO, "vary": {"label": ["boss's"]}}),
                       dict(JSON_TYPE, **AS_BOSS))
        bsweep, bqueued = bs["id"], bs["jobs"][0]  # boss has one job queued: his quota
        mine = self.run_one(u, Case("POST /v1/jobs", "/v1/jobs", dumps(dict(TWO, label="alice's")), AS_ALICE,
                                    expect=201)).json()["id"]
        u_cases = []
        guarded = [("GET /v1/openapi.json", "/v1/openapi.json", None), ("GET /v1/experiments", "/v1/experiments", None),
                   ("GET /v1/examples", "/v1/examples", None), ("POST /v1/jobs", "/v1/jobs", dumps(TWO)),
                   ("POST /v1/jobs", "/v1/jobs?dry_run=true", dumps(TWO)), ("GET /v1/jobs", "/v1/jobs", None),
                   ("GET /v1/jobs/{id}", f"/v1/jobs/{ub}", None), ("DELETE /v1/jobs/{id}", f"/v1/jobs/{ub}", None),
                   ("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{ub}/cancel", b""),
                   ("POST /v1/jobs/{id}/priority", f"/v1/jobs/{bqueued}/priority?value=1", b""),
                   ("GET /v1/jobs/{id}/curve", f"/v1/jobs/{ub}/curve", None),
                   ("GET /v1/jobs/{id}/curve.svg", f"/v1/jobs/{ub}/curve.svg", None),
                   ("GET /v1/jobs/{id}/snapshots", f"/v1/jobs/{ub}/snapshots", None),
                   ("GET /v1/jobs/{id}/snapshots/{k}", f"/v1/jobs/{ub}/snapshots/0", None),
                   ("GET /v1/jobs/{id}/snapshots/{k}.svg", f"/v1/jobs/{ub}/snapshots/0.svg", None),
                   ("GET /v1/jobs/{id}/archive", f"/v1/jobs/{ub}/archive", None),
                   ("POST /v1/sweeps", "/v1/sweeps", dumps({"spec": TWO, "vary": {"label": ["x"]}})),
                   ("GET /v1/sweeps", "/v1/sweeps", None), ("GET /v1/sweeps/{id}", f"/v1/sweeps/{bsweep}", None),
                   ("POST /v1/sweeps/{id}/cancel", f"/v1/sweeps/{bsweep}/cancel", b""),
                   ("GET /v1/sweeps/{id}/curves.svg", f"/v1/sweeps/{bsweep}/curves.svg", None)]
        for op, path, body in guarded:
            u_cases += [Case(op, path, body, expect=401, what="no token"),
                        Case(op, path, body, AS_NOBODY, expect=401, what="an unknown token")]
        u_cases.append(Case("GET /v1/jobs", "/v1/jobs", headers={"Authorization": TOKENS["alice"]}, expect=401,
                            what="a token without 'Bearer '"))
        for op, path in [("GET /", "/"), ("GET /web/app.js", "/web/app.js"), ("GET /web/style.css", "/web/style.css"),
                         ("GET /v1/health", "/v1/health")]:
            u_cases += [Case(op, path, expect=200, what="open: no token"),
                        Case(op, path, headers=AS_NOBODY, expect=200, what="open: an unknown token")]
        for op, tail, body in [("GET /v1/worker/jobs/{id}", "", None),
                               ("GET /v1/worker/jobs/{id}/checkpoint", "/checkpoint", None),
                               ("GET /v1/worker/jobs/{id}/checkpoint/{generation}/{index}", "/checkpoint/1/0", None),
                               ("POST /v1/worker/jobs/{id}/checkpoint/begin", "/checkpoint/begin", b""),
                               ("POST /v1/worker/jobs/{id}/checkpoint/{generation}/{index}", "/checkpoint/1/0",
                                b"\x00"),
                               ("POST /v1/worker/jobs/{id}/checkpoint",
                                "/checkpoint?generation=1&chunks=1&bytes=1&rows=0&snapshots=0", b""),
                               ("POST /v1/worker/jobs/{id}/begin", "/begin", dumps({"header": "a\n"})),
                               ("POST /v1/worker/jobs/{id}/results", "/results",
                                dumps({"first_index": 0, "lines": [], "snapshots": [], "progress": 0})),
                               ("POST /v1/worker/jobs/{id}/end", "/end", dumps({"outcome": "cancelled"}))]:
            h = {"Content-Type": "application/octet-stream"} if "checkpoint" in tail and body is not None else {}
            u_cases += [Case(op, f"/v1/worker/jobs/{ub}{tail}", body, h, expect=403, what="no worker secret, no token"),
                        Case(op, f"/v1/worker/jobs/{ub}{tail}", body, dict(h, **AS_BOSS), expect=403,
                             what="an admin's token is no worker secret")]
        # alice on boss's job and sweep (a private server: reads too).
        for op, path, body in guarded[6:]:
            if op in ("POST /v1/jobs", "POST /v1/sweeps", "GET /v1/jobs", "GET /v1/sweeps"):
                continue
            u_cases.append(Case(op, path, body, AS_ALICE, expect=403, what="another user's"))
        u_cases += [Case("GET /v1/jobs", "/v1/jobs?owner=boss", headers=AS_ALICE, expect=403, what="another's listing"),
                    Case("GET /v1/sweeps", "/v1/sweeps?owner=boss", headers=AS_ALICE, expect=403,
                         what="another's listing"),
                    Case("GET /v1/jobs", "/v1/jobs", headers=AS_ALICE, expect=200, what="her own"),
                    Case("GET /v1/jobs", "/v1/jobs?owner=alice", headers=AS_ALICE, expect=200, what="her own"),
                    Case("GET /v1/sweeps", "/v1/sweeps", headers=AS_ALICE, expect=200, what="her own"),
                    Case("GET /v1/jobs/{id}", f"/v1/jobs/{mine}", headers=AS_ALICE, expect=200, what="her own"),
                    Case("GET /v1/openapi.json", "/v1/openapi.json", headers=AS_ALICE, expect=200),
                    Case("GET /v1/experiments", "/v1/experiments", headers=AS_ALICE, expect=200),
                    Case("GET /v1/examples", "/v1/examples", headers=AS_ALICE, expect=200),
                    # A priority above 0 is an admin's (checked before the quota): 403, declared on both routes.
                    Case("POST /v1/jobs", "/v1/jobs?priority=5", dumps(dict(TWO, label="jump")), AS_ALICE, expect=403,
                         what="a non-admin's priority"),
                    Case("POST /v1/sweeps", "/v1/sweeps?priority=5", dumps({"spec": TWO, "vary": {"label": ["a"]}}),
                         AS_ALICE, expect=403, what="a non-admin's priority"),
                    # The quota: boss has a job queued, the limit is one.
                    Case("POST /v1/jobs", "/v1/jobs", dumps(dict(TWO, label="over quota")), AS_BOSS, expect=429),
                    Case("POST /v1/sweeps", "/v1/sweeps", dumps({"spec": TWO, "vary": {"label": ["a", "b"]}}),
                         AS_BOSS, expect=429),
                    Case("POST /v1/jobs", "/v1/jobs?dry_run=true", dumps(TWO), AS_BOSS, expect=200,
                         what="a dry run queues nothing"),
                    # An admin on alice's job, and on every listing.
                    Case("GET /v1/jobs/{id}", f"/v1/jobs/{mine}", headers=AS_BOSS, expect=200, what="an admin"),
                    Case("GET /v1/jobs/{id}/archive", f"/v1/jobs/{mine}/archive", headers=AS_BOSS, expect=200),
                    Case("GET /v1/jobs", "/v1/jobs?owner=alice", headers=AS_BOSS, expect=200, what="an admin"),
                    Case("GET /v1/sweeps", "/v1/sweeps?owner=boss", headers=AS_BOSS, expect=200),
                    Case("GET /v1/sweeps/{id}", f"/v1/sweeps/{bsweep}", headers=AS_BOSS, expect=200),
                    Case("POST /v1/jobs/{id}/priority", f"/v1/jobs/{mine}/priority?value=7", b"", AS_BOSS, expect=200,
                         what="an admin"),
                    Case("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{mine}/cancel", b"", AS_BOSS, expect=200,
                         what="an admin"),
                    Case("DELETE /v1/jobs/{id}", f"/v1/jobs/{mine}", headers=AS_ALICE, expect=200, what="her own"),
                    Case("POST /v1/sweeps/{id}/cancel", f"/v1/sweeps/{bsweep}/cancel", b"", AS_BOSS, expect=200),
                    Case("POST /v1/jobs/{id}/cancel", f"/v1/jobs/{ub}/cancel", b"", AS_BOSS, expect=202)]
        self.run_cases(u, u_cases)

        # -- `limits`: a full store, too many connections, a slow sender ------------------------------------------
        big = dict(CRYSTAL, label="x" * 200,
                   crystal={"grains_x": 20, "rows_z": 20, "layers_y": 5, "knockout": list(range(1500))})
        lim_cases = [Case("POST /v1/jobs", "/v1/jobs", dumps(big), expect=507, what="the store is full"),
                     Case("POST /v1/sweeps", "/v1/sweeps",
                          dumps({"spec": TWO, "vary": {"output.curve_points": list(range(1, 1001))}}), expect=507,
                          what="the store is full"),
                     Case("GET /v1/health", "/v1/health", expect=200)]
        self.run_cases(lim, lim_cases)
        self.current = lim
        held = []
        for _ in range(50):  # --max-connections 2: two requests that never end...
            if len(held) == 2:
                break
            s = socket.create_connection(("127.0.0.1", lim.port), timeout=5)
            s.sendall(b"GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
            if select.select([s], [], [], 0.1)[0]:  # refused at once: an earlier connection is still counted
                s.close()
                time.sleep(0.1)
            else:
                held.append(s)
        self.assertEqual(len(held), 2, "could not hold two connections open on `limits`")
        # ... a third connection is refused (503), and the two get 408 after --request-timeout 1.
        self.run_one(lim, Case("GET /v1/health", "/v1/health", raw=b"GET /v1/health HTTP/1.1\r\nHost: x\r\n\r\n",
                               expect=503, what="a third connection of at most 2"))
        for s in held:
            buf = read_answer(s, 5)
            s.close()
            got = parse_response(buf)
            answer = got[0] if got else Answer(None, {}, buf, "no answer within 5 s")
            case = Case("GET /v1/health", "/v1/health", expect=408, what="a request never finished", raw=b"")
            self.requests += 1
            self.per_op[case.op][answer.status] += 1
            self.judge(case, answer)

        # -- coverage and the verdict -------------------------------------------------------------------------
        for op in sorted(self.document.ops):
            if op not in self.per_op:
                self.violations.append({"kind": "operation not exercised by this test", "op": op, "case": op,
                                        "daemon": "-", "detail": "add cases for it"})
        never_2xx = [op for op in sorted(self.document.ops)
                     if op in self.per_op and not any(s and 200 <= s < 300 for s in self.per_op[op])]
        covered = sum(1 for op in self.document.ops if op in self.per_op)
        elapsed = time.time() - started
        lines = [f"\nOpenAPI conformance: {self.requests} requests, {covered} of {len(self.document.ops)} operations "
                 f"covered, {len(self.violations)} violations ({elapsed:.1f} s)"]
        lines.append("  answers by operation: " + "; ".join(
            f"{op} {dict(sorted((str(k), v) for k, v in self.per_op[op].items()))}" for op in sorted(self.per_op)))
        if never_2xx:
            lines.append(f"  operations no request could get a 2xx from (no job of a local daemon has a worker): "
                         f"{', '.join(never_2xx)}")
        groups = collections.OrderedDict()
        for v in sorted(self.violations, key=lambda v: (v["kind"], v["op"], v["case"])):
            groups.setdefault(v["kind"], []).append(v)
        for kind, items in groups.items():
            ops = sorted({v["op"] for v in items})
            lines.append(f"\n== {kind}: {len(items)} violation(s) in {len(ops)} operation(s)")
            for v in items:
                lines.append(f"  - {v['op']} <- {v['case']} ({v['daemon']}): {v['detail']}")
        print("\n".join(lines), file=sys.stderr)
        self.assertEqual(len(self.violations), 0,
                         f"{len(self.violations)} violations of the served OpenAPI document (listed above)")


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    if JSONSCHEMA_PROBLEM:
        print(f"SKIP: this test needs python3-jsonschema with Draft202012Validator (jsonschema >= 4): "
              f"{JSONSCHEMA_PROBLEM}", file=sys.stderr)
        sys.exit(SKIP_RETURN_CODE)
    skip_aware.main()
