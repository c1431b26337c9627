#!/usr/bin/python3
"""The bad-input suite (issue 10): hundreds of malformed requests against a real granulabd on loopback with
a real SQLite file, across every route and every spec field (the fields come from GET /v1/experiments, so a
new field is covered without editing this file). Every answer must be a 4xx with the JSON error shape (or a
documented 2xx), never a 5xx, the daemon must stay up, and every field-level error must name its field.

Standard library only; the daemon binary comes from $GRANULABD (set by CTest) or build/granulabd.
"""
import http.client
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
TINY = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 3}, "loading": {"rate_number": 1e-3},
        "output": {"curve_points": 5}}
RAW = "\u0000RAW\u0000"  # a placeholder string replaced by a raw token (1e400, NaN) after json.dumps


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def with_value(experiment, dotted, value):
    """A spec of `experiment` with the field at `dotted` (e.g. grain.size, crystal.knockout_regions[].x) set."""
    doc = {"experiment": experiment}
    parts = dotted.split(".")
    node = doc
    for k, part in enumerate(parts):
        last = k == len(parts) - 1
        if part.endswith("[]"):  # an array of objects: one element holding the rest
            item = {"x": 0, "z": 0, "radius": 1}
            node[part[:-2]] = [item]
            node = item
            continue
        if last:
            node[part] = value
        else:
            node = node.setdefault(part, {})
    return doc


def field_name(dotted):
    return dotted.replace("[]", "[0]")


def field_cases(experiments):
    """(name, body bytes, expected field or None): wrong values of every field of every experiment."""
    cases = []
    for e in experiments:
        for f in e["fields"]:
            name, kind = f["field"], f["type"]
            if name == "experiment":
                continue
            values = [("string", "x"), ("bool", True), ("array", []), ("object", {})]
            if kind in ("number", "integer"):
                values.append(("1e400", RAW + "1e400"))
                values.append(("-1e400", RAW + "-1e400"))
                values.append(("huge integer", RAW + "123456789012345678901234567890"))
                if "minimum" in f:
                    values.append(("below minimum", f["minimum"] - 1 - abs(f["minimum"])))
                if "maximum" in f:
                    values.append(("above maximum", f["maximum"] * 10 + 1))
                if kind == "integer":
                    values.append(("fraction", 2.5))
            elif kind == "string":
                values = [("number", 1), ("array", []), ("object", {})]
                if "choices" in f:
                    values.append(("unknown choice", "no-such-choice"))
                if "max_length" in f:
                    values.append(("too long", "x" * (f["max_length"] + 1)))
            elif kind.startswith("array"):
                values = [("string", "x"), ("number", 1), ("object", {})]
                if "numbers" in kind or "ids" in kind:
                    values.append(("element string", ["x"]))
                    values.append(("element 1e400", [RAW + "1e400"]))
                    if "maximum" in f:
                        values.append(("element above maximum", [f["maximum"] * 10 + 1]))
                    if "minimum" in f:
                        values.append(("element below minimum", [f["minimum"] - 1]))
                if "max_items" in f and ("numbers" in kind or "ids" in kind):
                    values.append(("too many items", [0] * (f["max_items"] + 1)))
            for label, value in values:
                text = json.dumps(with_value(e["name"], name, value))
                if isinstance(value, str) and value.startswith(RAW):
                    text = text.replace(json.dumps(value), value[len(RAW):])
                elif isinstance(value, list) and value and isinstance(value[0], str) and value[0].startswith(RAW):
                    text = text.replace(json.dumps(value[0]), value[0][len(RAW):])
                cases.append((f"{e['name']} {name} {label}", text.encode(), field_name(name)))
    return cases


def document_cases():
    """Malformed documents: (name, body bytes, expected field or None, expected status or None)."""
    deep = lambda n: ("[" * n + "]" * n).encode()
    c = [
        ("empty body", b"", None),
        ("whitespace", b"   \n", None),
        ("null", b"null", None),
        ("number", b"42", None),
        ("string", b'"spec"', None),
        ("array", b"[1, 2]", None),
        ("truncated", b'{"experiment": "two_cube_sliding"', None),
        ("trailing garbage", b'{"experiment": "two_cube_sliding"} xyz', None),
        ("NaN token", b'{"label": NaN}', None),
        ("Infinity token", b'{"label": Infinity}', None),
        ("-Infinity token", b'{"grain": {"size": -Infinity}}', None),
        ("single quotes", b"{'label': 'x'}", None),
        ("comment", b'{"label": "x" /* c */}', None),
        ("nesting 70", deep(70), None),
        ("nesting 100000", deep(100000), None),
        ("deep object", b'{"a":' * 70 + b"1" + b"}" * 70, None),
        ("invalid UTF-8 in a string", b'{"label": "\xff\xfe"}', None),
        ("invalid UTF-8 in a key", b'{"\xc3\x28": 1}', None),
        ("overlong UTF-8", b'{"label": "\xc0\xaf"}', None),
        ("lone surrogate escape", b'{"label": "\\ud800"}', None),
        ("NUL byte", b'{"label": "a\x00b"}', None),
        ("unknown top-level key", b'{"experiment": "two_cube_sliding", "bogus": 1}', "bogus"),
        ("unknown section key", b'{"experiment": "two_cube_sliding", "grain": {"bogus": 1}}', "grain.bogus"),
        ("unknown crystal key", b'{"experiment": "crystal_compression", "crystal": {"bogus": 1}}', "crystal.bogus"),
        ("unknown region key", b'{"experiment": "crystal_compression", "crystal": {"knockout_regions": '
                               b'[{"x": 0, "z": 0, "radius": 1, "bogus": 1}]}}', None),
        ("unknown experiment", b'{"experiment": "no_such_experiment"}', "experiment"),
        ("experiment number", b'{"experiment": 3}', "experiment"),
        ("duplicate key", b'{"experiment": "two_cube_sliding", "label": "a", "label": "b"}', "label"),
        ("duplicate nested key", b'{"grain": {"size": 0.01, "size": 0.02}}', "grain.size"),
        ("section is a number", b'{"grain": 5}', "grain"),
        ("section is a string", b'{"loading": "fast"}', "loading"),
        ("section is an array", b'{"material": []}', "material"),
        ("huge array label", json.dumps({"label": ["x"] * 200000}).encode(), "label"),
        ("huge string label", json.dumps({"label": "x" * 900000}).encode(), "label"),
        ("body over the limit", b'{"label": "' + b"x" * (1 << 21) + b'"}', None),
    ]
    return c


class BadInputTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="granulab_bad_input_")
        cls.db = os.path.join(cls.dir, "jobs.db")
        cls.port = free_port()
        cls.proc = None
        cls.log = open(os.path.join(cls.dir, "daemon.log"), "w+")
        # A finished job and a queued-then-cancelled one, for the routes that take an id.
        cls.start()
        cls.done = cls.call("POST", "/v1/jobs", json.dumps(TINY).encode())[1]["id"]
        deadline = time.time() + 60
        while cls.call("GET", f"/v1/jobs/{cls.done}")[1]["status"] != "succeeded" and time.time() < deadline:
            time.sleep(0.05)
        cls.stop()
        # From here no job can be accepted (1 MB budget): a spec that wrongly passed validation would be
        # refused with `over_budget`, and fail the field check, instead of running.
        cls.start("--max-memory", "1")

    @classmethod
    def start(cls, *extra):
        cls.proc = subprocess.Popen([DAEMON, "--port", str(cls.port), "--db", cls.db, "--workers", "1", "--threads", "1",
                                     *extra], stdout=cls.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                if cls.call("GET", "/v1/health")[0] == 200:
                    return
            except OSError:
                time.sleep(0.05)
        raise RuntimeError("granulabd did not start")

    @classmethod
    def stop(cls):
        if cls.proc and cls.proc.poll() is None:
            cls.proc.send_signal(signal.SIGTERM)
            cls.proc.wait(timeout=30)

    @classmethod
    def tearDownClass(cls):
        cls.stop()
        cls.log.close()

    @classmethod
    def call(cls, method, path, body=None, headers=None):
        conn = http.client.HTTPConnection("127.0.0.1", cls.port, timeout=30)
        try:
            conn.request(method, path, body=body, headers=headers or {})
            r = conn.getresponse()
            data = r.read()
        finally:
            conn.close()
        try:
            parsed = json.loads(data) if data else None
        except ValueError:
            parsed = None
        return r.status, parsed, data

    def answered(self, name, status, parsed, raw, field=None, expect=None):
        """One case's answer: no 5xx; a 4xx in the error shape; the field named when one is expected."""
        self.assertLess(status, 500, f"{name}: {status} {raw[:300]!r}")
        if expect is not None:
            self.assertEqual(status, expect, f"{name}: {raw[:300]!r}")
        if status >= 400:
            self.assertIsInstance(parsed, dict, f"{name}: not JSON: {raw[:300]!r}")
            error = parsed.get("error", {})
            self.assertTrue(error.get("code") and error.get("message"), f"{name}: {raw[:300]!r}")
            self.assertIn("field", error, name)
            if field is not None:
                self.assertTrue(error["field"] == field or error["field"].startswith(field + "["),
                                f"{name}: field {error['field']!r}, expected {field!r}: {error['message']}")
        self.counts[status // 100] = self.counts.get(status // 100, 0) + 1

    def alive(self):
        self.assertIsNone(self.proc.poll(), "granulabd died")
        self.assertEqual(self.call("GET", "/v1/health")[0], 200)

    def test_every_route_and_field(self):
        self.counts = {}
        experiments = self.call("GET", "/v1/experiments")[1]["experiments"]
        cases = 0
        # 1. Every spec field of every experiment, with wrong values.
        for k, (name, body, field) in enumerate(field_cases(experiments)):
            with self.subTest(name):
                status, parsed, raw = self.call("POST", "/v1/jobs", body, {"Content-Type": "application/json"})
                self.answered(name, status, parsed, raw, field=field, expect=400)
            cases += 1
            if k % 50 == 0:
                self.alive()
        # 2. Malformed documents.
        for name, body, field in document_cases():
            with self.subTest(name):
                status, parsed, raw = self.call("POST", "/v1/jobs", body, {"Content-Type": "application/json"})
                self.answered(name, status, parsed, raw, field=field)
                self.assertIn(status, (400, 413), name)
            cases += 1
        self.alive()
        # 3. Content types and query parameters of the submit route.
        spec = json.dumps(TINY).encode()
        for name, path, headers in [
            ("text/plain", "/v1/jobs", {"Content-Type": "text/plain"}),
            ("no content type", "/v1/jobs", {}),
            ("form content type", "/v1/jobs", {"Content-Type": "application/x-www-form-urlencoded"}),
            ("priority word", "/v1/jobs?priority=high", {}),
            ("priority 1e9", "/v1/jobs?priority=1000000000", {}),
            ("priority %FF", "/v1/jobs?priority=%FF", {}),
            ("reuse junk", "/v1/jobs?reuse=%00", {}),
        ]:
            with self.subTest(name):
                status, parsed, raw = self.call("POST", path, spec, headers)
                self.answered(name, status, parsed, raw, field="priority" if "priority" in path else None)
            cases += 1
        # 4. Paths and queries of every route.
        d = self.done
        requests = [
            ("GET", "/v1/jobs/99999999999999999999999", 404, None),
            ("GET", "/v1/jobs/0", 404, None),
            ("GET", "/v1/jobs/-1", 404, None),
            ("GET", "/v1/jobs/%00", 404, None),
            ("GET", "/v1/jobs/1%2F..%2Fhealth", 404, None),
            ("GET", "/v1/jobs/../v1/health", None, None),
            ("GET", "/v1/jobs/" + "9" * 5000, None, None),
            ("GET", "/v1/" + "x" * 20000, None, None),
            ("GET", f"/v1/jobs/{d}/snapshots/99999999999999999999", 404, None),
            ("GET", f"/v1/jobs/{d}/snapshots/2147483648", 404, None),
            ("GET", f"/v1/jobs/{d}/snapshots/-1", 404, None),
            ("GET", f"/v1/jobs/{d}/curve?format=bogus", 400, "format"),
            ("GET", f"/v1/jobs/{d}/curve?format=%FF", 400, "format"),
            ("GET", f"/v1/jobs/{d}/curve?format=csv", 200, None),
            ("GET", f"/v1/jobs/{d}/curve", 200, None),
            ("GET", "/v1/jobs?limit=%FF", 400, "limit"),
            ("GET", "/v1/jobs?limit=-1", 400, "limit"),
            ("GET", "/v1/jobs?limit=0", 400, "limit"),
            ("GET", "/v1/jobs?limit=99999999999999999999", 400, "limit"),
            ("GET", "/v1/jobs?limit=1e3", 400, "limit"),
            ("GET", "/v1/jobs?limit=", 400, "limit"),
            ("GET", "/v1/jobs?offset=-5", 400, "offset"),
            ("GET", "/v1/jobs?offset=2147483648", 200, None),
            ("GET", "/v1/jobs?offset=4294967297", 200, None),
            ("GET", "/v1/jobs?offset=99999999999999999999", 400, "offset"),
            ("GET", "/v1/jobs?status=bogus", 400, "status"),
            ("GET", "/v1/jobs?status=%FF%FE", 400, "status"),
            ("GET", "/v1/jobs?owner=%FF", 200, None),
            ("GET", "/v1/jobs?owner=" + "x" * 10000, 414, None),
            ("GET", "/v1/jobs?limit=5&limit=6", None, None),
            ("GET", "/v1/jobs?%zz=1", None, None),
            ("POST", f"/v1/jobs/{d}/cancel", 409, None),
            ("POST", "/v1/jobs/99999999999999999999999/cancel", 404, None),
            ("POST", f"/v1/jobs/{d}/priority", 400, "value"),
            ("POST", f"/v1/jobs/{d}/priority?value=x", 400, "value"),
            ("POST", f"/v1/jobs/{d}/priority?value=1000", 400, "value"),
            ("POST", f"/v1/jobs/{d}/priority?value=5", 409, None),
            ("DELETE", "/v1/jobs/99999999999999999999999", 404, None),
            ("PUT", "/v1/jobs", None, None),
            ("PATCH", f"/v1/jobs/{d}", None, None),
            ("DELETE", "/v1/jobs", None, None),
            ("PUT", "/v1/health", None, None),
            ("POST", "/v1/health", None, None),
            ("DELETE", "/v1/experiments", None, None),
            ("GET", f"/v1/jobs/{d}/cancel", None, None),
            ("OPTIONS", "/v1/jobs", None, None),
            ("HEAD", "/v1/health", None, None),
            ("TRACE", "/v1/jobs", None, None),
            ("GET", "/", 404, None),
            ("GET", "/v2/jobs", 404, None),
        ]
        for method, path, expect, field in requests:
            name = f"{method} {path[:80]}"
            with self.subTest(name):
                status, parsed, raw = self.call(method, path)
                if method == "HEAD":
                    self.assertLess(status, 500)
                else:
                    self.answered(name, status, parsed, raw, field=field, expect=expect)
            cases += 1
        self.alive()
        # 5. Bytes no HTTP client library would send.
        raw_requests = [
            ("no Content-Length", f"POST /v1/jobs/{d}/cancel HTTP/1.1\r\nHost: x\r\n\r\n".encode(), 409),
            ("Content-Length word", b"POST /v1/jobs HTTP/1.1\r\nHost: x\r\nContent-Length: many\r\n\r\n", 400),
            ("Content-Length 1e30", b"POST /v1/jobs HTTP/1.1\r\nContent-Length: 1000000000000000000000000000\r\n\r\n", 413),
            ("two Content-Lengths", b"POST /v1/jobs HTTP/1.1\r\nContent-Length: 2\r\nContent-Length: 3\r\n\r\n{}", 400),
            ("unknown transfer coding", b"POST /v1/jobs HTTP/1.1\r\nTransfer-Encoding: gzip\r\n\r\n", 400),
            ("bad chunk size", b"POST /v1/jobs HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n", 400),
            ("chunk over the limit", b"POST /v1/jobs HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n200000\r\n", 413),
            ("head over 16 KiB", b"GET /v1/health HTTP/1.1\r\nX-Big: " + b"x" * 20000 + b"\r\n\r\n", 431),
            ("header without colon", b"GET /v1/health HTTP/1.1\r\nnonsense\r\n\r\n", 400),
            ("Expect something else", b"POST /v1/jobs HTTP/1.1\r\nExpect: 200-ok\r\nContent-Length: 2\r\n\r\n{}", 417),
            ("request line junk", b"\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03\r\n\r\n", None),
            ("HTTP/0.9 style", b"GET /\r\n\r\n", None),
            ("HTTP/1.0", b"GET /v1/health HTTP/1.0\r\n\r\n", 200),
        ]
        for name, data, expect in raw_requests:
            with self.subTest(name):
                with socket.create_connection(("127.0.0.1", self.port), timeout=10) as s:
                    s.sendall(data)
                    got = b""
                    try:
                        while b"\r\n\r\n" not in got or len(got) < got.find(b"\r\n\r\n") + 4 + self.length(got):
                            chunk = s.recv(65536)
                            if not chunk:
                                break
                            got += chunk
                    except socket.timeout:
                        pass
                if not got:  # closed without an answer: allowed only for bytes that are not HTTP at all
                    self.assertIsNone(expect, f"{name}: no answer")
                    continue
                status = int(got.split(b" ", 2)[1])
                body = got.split(b"\r\n\r\n", 1)[1]
                try:
                    parsed = json.loads(body) if body else None
                except ValueError:
                    parsed = None
                self.answered(name, status, parsed, got, expect=expect)
            cases += 1
        self.alive()
        print(f"\nbad-input suite: {cases} cases, {self.counts.get(4, 0)} answered 4xx, {self.counts.get(2, 0)} 2xx, "
              f"{self.counts.get(5, 0)} 5xx, daemon alive", file=sys.stderr)
        self.assertGreaterEqual(cases, 300)
        self.assertEqual(self.counts.get(5, 0), 0)

    @staticmethod
    def length(response):
        head = response.split(b"\r\n\r\n", 1)[0].lower()
        for line in head.split(b"\r\n"):
            if line.startswith(b"content-length:"):
                return int(line.split(b":")[1])
        return 0


if __name__ == "__main__":
    unittest.main()
