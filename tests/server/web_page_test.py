#!/usr/bin/python3
"""The web page at / in a real browser (Debian's headless Chromium, driven over the DevTools protocol on a
pipe): it lists submitted jobs with their status and keeps them live, shows a job's curve and snapshot
sections, a sweep's overlaid curves and table (a long legend drawn inside the picture), reports a bad field
next to that field and submits a good spec (a field's allowed values as a menu, its range as it is: "(0, 1]"),
asks for a token once on a server that needs one, and shows "none" and why, never a number, where a crystal has no
first yield (the job's key values, its picture's legend, the sweep's table).

Standard library only. The daemon comes from $GRANULABD (set by CTest) or build/granulabd; Chromium from
$CHROMIUM or /usr/bin/chromium (the test is skipped, loudly, when there is none).
"""
import json
import os
import shutil
import signal
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
DAEMON = os.environ.get("GRANULABD") or os.path.join(ROOT, "build", "granulabd")
CHROMIUM = os.environ.get("CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"

TWO_CUBE = {"experiment": "two_cube_sliding", "grain": {"edge_spheres": 4}, "loading": {"rate_number": 1e-4},
            "output": {"curve_points": 20}, "label": "web two cubes"}
CRYSTAL = {"experiment": "crystal_compression", "grain": {"shape": "rhombic_dodecahedron", "edge_spheres": 3},
           "crystal": {"grains_x": 3, "rows_z": 6, "layers_y": 3},
           "loading": {"confining_pressure": 30000, "max_strain": 0.004, "rate_number": 1e-4},
           "run": {"time_step_factor": 0.4},
           "output": {"curve_points": 40, "snapshot_strains": [0, 0.004]}, "label": "web crystal"}
# Simple-cubic cubes loaded along [0 0 1] (about 0.1 s): columns of cubes carry the load face to face and never give
# way, so the curve never falls: no first yield and no peak, each with its reason (issue 51).
LOCKED = {"experiment": "crystal_compression", "label": "sc locked", "grain": {"edge_spheres": 2},
          "crystal": {"lattice": "sc", "grains_x": 2, "layers_y": 2, "rows_z": 3},
          "loading": {"confining_pressure": 30000, "max_strain": 0.0005, "rate_number": 1e-3},
          "output": {"curve_points": 4, "snapshot_strains": []}}


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Daemon:
    def __init__(self, directory, *extra):
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.token = None
        self.proc = subprocess.Popen([DAEMON, "--port", str(self.port), "--db", os.path.join(directory, "jobs.db"),
                                      "--workers", "1", "--threads", "1", *extra],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.time() + 20
        while time.time() < deadline:
            try:
                urllib.request.urlopen(self.url + "/v1/health", timeout=2)
                return
            except Exception:
                time.sleep(0.05)
        self.stop()
        raise RuntimeError("granulabd did not start")

    def call(self, method, path, body=None):
        request = urllib.request.Request(self.url + path, method=method,
                                         data=None if body is None else json.dumps(body).encode())
        if self.token:
            request.add_header("Authorization", "Bearer " + self.token)
        with urllib.request.urlopen(request, timeout=10) as response:
            return json.loads(response.read())

    def text(self, path):
        request = urllib.request.Request(self.url + path)
        if self.token:
            request.add_header("Authorization", "Bearer " + self.token)
        with urllib.request.urlopen(request, timeout=10) as response:
            return response.read().decode()

    def wait(self, job, seconds=90):
        deadline = time.time() + seconds
        while time.time() < deadline:
            status = self.call("GET", f"/v1/jobs/{job}")["status"]
            if status not in ("queued", "running"):
                return status
            time.sleep(0.1)
        raise AssertionError(f"job {job} did not finish")

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            self.proc.wait(timeout=30)


class Browser:
    """Headless Chromium driven over the DevTools protocol on a pipe (fd 3 in, fd 4 out, NUL-separated JSON)."""

    def __init__(self, directory):
        to_chrome_r, self.to_chrome = os.pipe()
        self.from_chrome, from_chrome_w = os.pipe()
        # The child gets our ends as its fds 3 and 4 (copied high first, so neither overwrites the other).
        def child_fds():
            r, w = os.dup(to_chrome_r) + 10, os.dup(from_chrome_w) + 10
            os.dup2(r - 10, r), os.dup2(w - 10, w)
            os.dup2(r, 3)
            os.dup2(w, 4)
        self.proc = subprocess.Popen([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-pipe",
                                      "--user-data-dir=" + os.path.join(directory, "profile"), "--no-first-run",
                                      "--window-size=1280,1400", "about:blank"],
                                     preexec_fn=child_fds, pass_fds=(3, 4),
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self.buffer = b""
        self.next_id = 0
        self.session = None

    def send(self, method, params=None, session=True):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session and self.session:
            message["sessionId"] = self.session
        os.write(self.to_chrome, json.dumps(message).encode() + b"\0")
        while True:
            while b"\0" not in self.buffer:
                chunk = os.read(self.from_chrome, 1 << 16)
                if not chunk:
                    raise RuntimeError("chromium closed the pipe")
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def open(self, url):
        if self.session is None:
            target = self.send("Target.createTarget", {"url": "about:blank"}, session=False)["targetId"]
            self.session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True}, session=False)["sessionId"]
            self.send("Page.enable")
        self.send("Page.navigate", {"url": url})

    def js(self, expression):
        result = self.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True, "returnByValue": True})
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def until(self, expression, seconds=20):
        """The expression's value once it is truthy; fails with the last value after `seconds`."""
        deadline = time.time() + seconds
        value = None
        while time.time() < deadline:
            try:
                value = self.js(expression)
            except RuntimeError:
                value = None  # the page is still loading
            if value:
                return value
            time.sleep(0.1)
        raise AssertionError(f"not true after {seconds} s: {expression} (last: {value!r})")

    def close(self):
        try:
            self.send("Browser.close", session=False)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self.to_chrome)
        os.close(self.from_chrome)


@unittest.skipUnless(os.path.exists(CHROMIUM), "Debian's chromium is not installed (make test installs it)")
class WebPageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="granulab_web_")
        cls.daemon = Daemon(cls.dir)
        cls.browser = Browser(cls.dir)

    @classmethod
    def tearDownClass(cls):
        cls.browser.close()
        cls.daemon.stop()
        shutil.rmtree(cls.dir, ignore_errors=True)

    def row_status(self, job):
        return f"(document.querySelector('#jobs tr[data-id=\"{job}\"] .status') || {{}}).textContent"

    def test_the_list_shows_a_submitted_job_and_follows_it_to_the_end(self):
        self.browser.open(self.daemon.url + "/#/")
        self.browser.until("document.querySelector('#jobs') !== null")
        job = self.daemon.call("POST", "/v1/jobs", TWO_CUBE)["id"]
        # Appears without a reload, with its label and a progress bar, and ends succeeded on the same page.
        self.assertIn(self.browser.until(self.row_status(job)), ("queued", "running", "succeeded"))
        row = f"document.querySelector('#jobs tr[data-id=\"{job}\"]')"
        self.assertIn("web two cubes", self.browser.js(row + ".textContent"))
        self.assertTrue(self.browser.js(row + ".querySelector('.progress') !== null"))
        self.assertEqual(self.browser.until(f"{self.row_status(job)} === 'succeeded' && 'succeeded'", 90), "succeeded")
        self.assertIn("100 %", self.browser.js(row + ".textContent"))

    def test_a_job_page_shows_its_curve_and_snapshot_sections(self):
        job = self.daemon.call("POST", "/v1/jobs", CRYSTAL)["id"]
        self.assertEqual(self.daemon.wait(job), "succeeded")
        self.browser.open(f"{self.daemon.url}/#/jobs/{job}")
        # The server's curve picture, inline: deviator and the two platens, and the dashed yield estimate.
        self.assertEqual(self.browser.until("document.querySelectorAll('#curve svg polyline.series:not([stroke-dasharray])').length"), 3)
        self.assertEqual(self.browser.js("document.querySelectorAll('#curve svg polyline.series[stroke-dasharray]').length"), 1)
        self.assertIn("first yield", self.browser.js("document.querySelector('#curve svg').textContent"))
        # The headline's key values in the crystal's natural unit, and its summary tables (one segment here).
        key_values = self.browser.until("document.getElementById('key-values') && "
                                        "document.getElementById('key-values').textContent")
        self.assertRegex(key_values, r"first yield [0-9.]+ p0 at [0-9.e-]+ %; peak [0-9.]+ p0")
        self.assertIn("loading segments", self.browser.until("document.getElementById('summary-tables').textContent"))
        self.assertEqual(self.browser.js("document.querySelectorAll('#summary-tables tr').length"), 2)
        # The column chooser draws one column; the units chooser redraws in SI (kPa instead of p0).
        self.assertIn("stress (p0)", self.browser.js("document.querySelector('#curve svg').textContent"))
        self.browser.js("""(() => { const y = document.getElementById('curve-y'); y.value = 'lateral_stress';
                           y.dispatchEvent(new Event('change')); })()""")
        self.assertEqual(self.browser.until("(() => { const s = document.querySelectorAll('#curve svg polyline.series');"
                                            " return s.length === 1 && s[0].getAttribute('data-label'); })()"),
                         "lateral_stress")
        self.browser.js("""(() => { const y = document.getElementById('curve-y'); y.value = '';
                           const u = document.getElementById('curve-units'); u.value = 'si';
                           u.dispatchEvent(new Event('change')); })()""")
        self.assertTrue(self.browser.until("document.querySelectorAll('#curve svg polyline.series:not([stroke-dasharray])').length === 3 && "
                                           "document.querySelector('#curve svg').textContent.includes('stress (kPa)')"))
        # The latest snapshot's section: one hexagon per grain of the middle layer (3 x 6).
        self.assertEqual(self.browser.until("document.querySelectorAll('#snapshot svg polygon.grain').length"), 18)
        # Another field and layer redraw it.
        self.browser.js("""(() => { const f = document.getElementById('snapshot-field'); f.value = 'displacement';
                           const s = document.getElementById('snapshot-slice'); s.value = '0';
                           s.dispatchEvent(new Event('change')); })()""")
        self.assertTrue(self.browser.until("document.querySelector('#snapshot svg') && "
                                           "document.querySelector('#snapshot svg').textContent.includes('displacement (mm)') && "
                                           "document.querySelector('#snapshot svg').textContent.includes('layer 0')"))
        self.assertEqual(self.browser.js("document.querySelectorAll('#snapshot svg polygon.grain').length"), 18)
        links = self.browser.js("Array.from(document.querySelectorAll('.downloads a')).map(a => a.textContent)")
        for name in ("curve.csv", "everything (.tar)", "dump", "vtk", "dic_csv", "dic_vtk"):
            self.assertIn(name, links)
        # The snapshot's slip bands as a table (the job's summary has them) and the front face's DIC-like map, one
        # square per measured node; a coarser grid step redraws it with fewer.
        summary = self.daemon.call("GET", f"/v1/jobs/{job}")["summary"]
        bands = summary["snapshots"][-1]["slip_bands"]
        self.assertIn("Slip bands", self.browser.until("document.getElementById('slip-bands').textContent"))
        self.assertEqual(self.browser.js("document.querySelectorAll('#slip-band-table tr.slip-band').length"), len(bands))
        fine = self.browser.until("document.querySelectorAll('#dic svg g.dic-map rect').length")
        self.assertGreater(fine, 18)
        self.assertIn("max shear strain", self.browser.js("document.querySelector('#dic svg').textContent"))
        self.browser.js("""(() => { const s = document.getElementById('dic-step'); s.value = '0.004';
                           const f = document.getElementById('dic-field'); f.value = 'ezz';
                           s.dispatchEvent(new Event('change')); })()""")
        self.assertTrue(self.browser.until("document.querySelector('#dic svg') && "
                                           "document.querySelector('#dic svg').textContent.includes('axial strain Ezz')"))
        self.assertLess(self.browser.js("document.querySelectorAll('#dic svg g.dic-map rect').length"), fine)

    def test_a_sweep_page_overlays_its_curves_and_tabulates_its_jobs(self):
        sweep = self.daemon.call("POST", "/v1/sweeps", {"spec": TWO_CUBE, "vary": {"material.friction": [0.1, 0.3]},
                                                        "label": "web friction sweep"})
        for job in sweep["jobs"]:
            self.assertEqual(self.daemon.wait(job), "succeeded")
        self.browser.open(f"{self.daemon.url}/#/sweeps/{sweep['id']}")
        self.assertEqual(self.browser.until("document.querySelectorAll('#curves svg polyline.series').length"), 2)
        rows = self.browser.until("document.querySelectorAll('#sweep-jobs tr[data-id]').length === 2 && "
                                  "Array.from(document.querySelectorAll('#sweep-jobs tr[data-id]')).map(r => r.textContent)")
        self.assertIn("0.1", rows[0])
        self.assertIn("0.3", rows[1])
        self.assertIn("succeeded", rows[0])
        # The table's columns are the two cubes' headline values, not a crystal's first yield.
        headers = self.browser.js("Array.from(document.querySelectorAll('#sweep-jobs th')).map(h => h.textContent)")
        self.assertIn("friction ratio T / P", headers)
        self.assertNotIn("first yield (p0)", headers)

    def test_a_crystal_that_never_yields_shows_none_and_why_never_a_number(self):
        job = self.daemon.call("POST", "/v1/jobs", LOCKED)["id"]
        sweep = self.daemon.call("POST", "/v1/sweeps", {"spec": LOCKED, "vary": {"loading.confining_pressure": [20000, 30000]}})
        for j in [job] + sweep["jobs"]:
            self.assertEqual(self.daemon.wait(j), "succeeded")
        summary = self.daemon.call("GET", f"/v1/jobs/{job}")["summary"]
        self.assertIs(summary["first_yield"]["found"], False)
        self.assertIs(summary["peak"]["found"], False)
        reason = summary["first_yield"]["reason"]
        self.assertRegex(reason, r"^none to [0-9.]+ % strain")

        # The job page's key values: the reason where the number would be.
        self.browser.open(f"{self.daemon.url}/#/jobs/{job}")
        key_values = self.browser.until("document.getElementById('key-values') && "
                                        "document.getElementById('key-values').textContent")
        self.assertIn("first yield: none to", key_values)
        self.assertIn("first yield: " + reason, key_values)
        self.assertIn("peak: " + summary["peak"]["reason"], key_values)
        self.assertNotRegex(key_values, r"(first yield|peak) [0-9]")
        # Its curve picture, inline: the legend names it, and no marker stands on the curve.
        self.assertIn("first yield: none to", self.browser.until(
            "document.querySelector('#curve svg g.legend') && document.querySelector('#curve svg g.legend').textContent"))
        self.assertEqual(self.browser.js("document.querySelectorAll('#curve svg g.marker').length"), 0)
        # The picture as the server draws it: each legend entry's lines joined again.
        svg = ET.fromstring(self.daemon.text(f"/v1/jobs/{job}/curve.svg"))
        groups = [g for g in svg.iter() if g.tag.split("}")[-1] == "g"]
        legend = next(g for g in groups if g.get("class") == "legend")
        entries = [" ".join(" ".join(t.itertext()).split()) for t in legend if t.tag.split("}")[-1] == "text"]
        self.assertTrue(any(e.startswith("first yield: none to") for e in entries), entries)
        self.assertIn("first yield: " + reason, entries)
        self.assertFalse([e for e in entries if e.startswith("first yield") and not e.startswith("first yield: ")], entries)
        markers = [g.get("data-label") for g in groups if g.get("class") == "marker"]
        self.assertEqual(markers, [])  # neither first yield nor peak is a point of the curve

        # The sweep page's table: "none" in the first yield's cell, the reason beneath it, no number of its own.
        reasons = {j["id"]: j["first_yield"]["reason"] for j in self.daemon.call("GET", f"/v1/sweeps/{sweep['id']}")["jobs"]}
        self.browser.open(f"{self.daemon.url}/#/sweeps/{sweep['id']}")
        cells = self.browser.until("""(() => {
            const heads = Array.from(document.querySelectorAll('#sweep-jobs th')).map(h => h.textContent);
            const at = heads.indexOf('first yield (p0)');
            const rows = Array.from(document.querySelectorAll('#sweep-jobs tr[data-id]'));
            if (at < 0 || rows.length !== 2 || rows.some(r => !r.textContent.includes('succeeded'))) return null;
            return rows.map(r => { const td = r.children[at], below = td.querySelector('div');
              return {id: Number(r.dataset.id), numeric: td.classList.contains('num'), text: td.textContent,
                      own: Array.from(td.childNodes).filter(n => n.nodeType === 3).map(n => n.textContent).join(''),
                      reason: below ? below.textContent : null, title: td.title}; }); })()""")
        self.assertEqual(sorted(c["id"] for c in cells), sorted(sweep["jobs"]))
        for cell in cells:
            self.assertEqual(cell["own"], "none", cell)
            self.assertEqual(cell["reason"], reasons[cell["id"]], cell)
            self.assertEqual(cell["title"], reasons[cell["id"]], cell)
            self.assertEqual(cell["text"], "none" + reasons[cell["id"]], cell)  # nothing else: no value, no "at"
            self.assertFalse(cell["numeric"], cell)

    def test_a_sweep_picture_keeps_long_labels_inside_it(self):
        # Five varied values and a status make a label of about 110 characters (issue 51: such a legend ran off a
        # 930 px picture). Cancelled at once: the picture of jobs without rows still has its legend.
        vary = {"material.friction": [0.123456], "material.damping": [0.0512345], "loading.rate_number": [0.000123456],
                "output.curve_points": [21], "grain.edge_spheres": [3]}
        sweep = self.daemon.call("POST", "/v1/sweeps", {"spec": TWO_CUBE, "vary": vary, "mode": "zip"})
        self.daemon.call("POST", f"/v1/sweeps/{sweep['id']}/cancel")
        self.browser.open(f"{self.daemon.url}/v1/sweeps/{sweep['id']}/curves.svg")
        # Where each line of the legend's text ends as Chromium draws it, and the picture's width.
        drawn = self.browser.until("""(() => { const svg = document.documentElement;
            const texts = Array.from(document.querySelectorAll('g.legend text'));
            if (svg.tagName !== 'svg' || !texts.length) return null;
            const ends = [];
            for (const t of texts) {
              const lines = t.querySelectorAll('tspan').length ? Array.from(t.querySelectorAll('tspan')) : [t];
              for (const l of lines) { const b = l.getBBox(); ends.push(b.x + b.width); }
            }
            return {width: svg.width.baseVal.value, ends: ends,
                    text: texts.map(t => t.textContent).join(' | ')}; })()""")
        self.assertIn("edge_spheres = 3", drawn["text"])
        self.assertGreater(len(drawn["ends"]), 1, drawn)  # wrapped
        for end in drawn["ends"]:
            self.assertLessEqual(end, drawn["width"], drawn)

    def test_the_form_names_a_bad_field_next_to_it_and_submits_a_good_spec(self):
        self.browser.open(self.daemon.url + "/#/submit")
        self.browser.until("document.getElementById('f-loading.max_slide') !== null")
        self.browser.js("""document.getElementById('f-loading.max_slide').value = '7';
                           document.getElementById('submit').click()""")
        message = self.browser.until("(() => { const e = document.getElementById('e-loading.max_slide');"
                                     " return e && !e.hidden && e.textContent; })()")
        self.assertIn("max_slide", message)
        self.assertTrue(self.browser.js("document.getElementById('f-loading.max_slide').classList.contains('bad')"))
        before = len(self.daemon.call("GET", "/v1/jobs?limit=1000")["jobs"])
        self.browser.js("""(() => { const set = (k, v) => document.getElementById('f-' + k).value = v;
                           set('loading.max_slide', '0.1'); set('grain.edge_spheres', '4'); set('output.curve_points', '5');
                           set('label', 'from the form'); document.getElementById('submit').click(); })()""")
        job = int(self.browser.until("(location.hash.match(/^#\\/jobs\\/(\\d+)$/) || [])[1]"))
        self.assertEqual(len(self.daemon.call("GET", "/v1/jobs?limit=1000")["jobs"]), before + 1)
        spec = self.daemon.call("GET", f"/v1/jobs/{job}")["spec"]
        self.assertEqual(spec["label"], "from the form")
        self.assertEqual(spec["loading"]["max_slide"], 0.1)
        self.assertEqual(spec["grain"]["edge_spheres"], 4)
        self.assertEqual(self.browser.until("document.querySelector('#job-head h1') && "
                                            "document.querySelector('#job-head h1').textContent"), f"Job {job}: from the form")

    def test_the_form_offers_a_fields_values_as_a_menu_and_shows_ranges_as_they_are(self):
        described = {e["name"]: {f["field"]: f for f in e["fields"]}
                     for e in self.daemon.call("GET", "/v1/experiments")["experiments"]}
        self.browser.open(self.daemon.url + "/#/submit")
        self.browser.until("document.getElementById('f-contact.tangential') !== null")
        menu = self.browser.js("""(() => { const s = document.getElementById('f-contact.tangential');
            return {tag: s.tagName, options: Array.from(s.options).map(o => o.value), value: s.value}; })()""")
        self.assertEqual(menu["tag"], "SELECT")
        self.assertEqual(menu["options"], described["two_cube_sliding"]["contact.tangential"]["choices"])
        self.assertEqual(menu["value"], described["two_cube_sliding"]["contact.tangential"]["default"])
        self.assertEqual(self.browser.js("document.getElementById('f-grain.size').tagName"), "INPUT")  # a number

        def meaning(field):
            return self.browser.js(f"document.getElementById('f-{field}').nextElementSibling.textContent")
        # grain.size > 0: the bound itself is not allowed; grain.overlap may be 0.
        self.assertTrue(described["two_cube_sliding"]["grain.size"]["exclusive_minimum"])
        self.assertIn("(0, 1]", meaning("grain.size"))
        self.assertIn("[0, 0.95]", meaning("grain.overlap"))
        # A crystal: an upper bound that is another field's value is named, a list's range is each value's.
        self.browser.js("""(() => { const s = document.getElementById('experiment'); s.value = 'crystal_compression';
                           s.dispatchEvent(new Event('change')); })()""")
        self.browser.until("document.getElementById('f-crystal.lattice') !== null")
        self.assertEqual(self.browser.js("Array.from(document.getElementById('f-crystal.lattice').options).map(o => o.value)"),
                         described["crystal_compression"]["crystal.lattice"]["choices"])
        self.assertIn("each in [0, loading.max_strain]", meaning("output.snapshot_strains"))
        self.assertNotIn("undefined", self.browser.js("document.getElementById('spec-form').textContent"))
        # A value chosen from the menu is the one submitted.
        self.browser.js("""(() => { const s = document.getElementById('experiment'); s.value = 'two_cube_sliding';
                           s.dispatchEvent(new Event('change')); })()""")
        self.browser.until("document.getElementById('f-contact.tangential') !== null")
        self.browser.js("""(() => { const set = (k, v) => document.getElementById('f-' + k).value = v;
                           set('contact.tangential', 'mindlin'); set('loading.max_slide', '0.1');
                           set('grain.edge_spheres', '4'); set('output.curve_points', '5'); set('label', 'a menu');
                           document.getElementById('submit').click(); })()""")
        job = int(self.browser.until("(location.hash.match(/^#\\/jobs\\/(\\d+)$/) || [])[1]"))
        self.assertEqual(self.daemon.call("GET", f"/v1/jobs/{job}")["spec"]["contact"]["tangential"], "mindlin")

    def test_the_form_starts_from_a_quick_crystal_shows_the_cost_and_asks_before_a_long_job(self):
        self.browser.open(self.daemon.url + "/#/submit")
        self.browser.until("document.getElementById('experiment') !== null")
        self.browser.js("""(() => { const s = document.getElementById('experiment'); s.value = 'crystal_compression';
                           s.dispatchEvent(new Event('change')); })()""")
        # The first example offered is the cheapest: the quick crystal, not the 864-grain reference.
        self.assertEqual(self.browser.until("document.getElementById('example').value === 'crystal_quick' && "
                                            "document.getElementById('example').value"), "crystal_quick")
        with open(os.path.join(ROOT, "examples", "crystal_quick.json")) as f:
            expected = self.daemon.call("POST", "/v1/jobs?dry_run=true", json.load(f))
        line = self.browser.until("(document.getElementById('submit-cost') || {}).textContent || ''")
        self.assertIn("Expected: about", line)
        self.assertIn("%g steps" % float("%.3g" % expected["steps"]), line)
        self.assertIn("confinement", line)
        # A slow, long run: the line turns into a warning, and Submit asks first (answered no: nothing queued).
        before = len(self.daemon.call("GET", "/v1/jobs?limit=1000")["jobs"])
        self.browser.js("""(() => { window.asked = '';  window.confirm = (m) => { window.asked = m; return false; };
                           const i = document.getElementById('f-loading.rate_number'); i.value = '4e-8';
                           i.dispatchEvent(new Event('input', { bubbles: true })); })()""")
        self.browser.until("document.querySelector('#submit-cost .warning') !== null")
        self.browser.js("document.getElementById('submit').click()")
        asked = self.browser.until("window.asked")
        self.assertIn("expected to take about", asked)
        self.assertIn("not submitted", self.browser.until("document.getElementById('submit-message').textContent"))
        self.assertEqual(len(self.daemon.call("GET", "/v1/jobs?limit=1000")["jobs"]), before)


@unittest.skipUnless(os.path.exists(CHROMIUM), "Debian's chromium is not installed (make test installs it)")
class WebPageWithTokensTest(unittest.TestCase):
    def test_the_page_asks_for_the_token_once_and_keeps_it(self):
        directory = tempfile.mkdtemp(prefix="granulab_web_tokens_")
        tokens = os.path.join(directory, "tokens")
        with open(tokens, "w") as f:
            f.write("ada s3cret-ada\n")
        os.chmod(tokens, 0o600)
        daemon = Daemon(directory, "--token-file", tokens)
        browser = Browser(directory)
        try:
            daemon.token = "s3cret-ada"
            job = daemon.call("POST", "/v1/jobs", TWO_CUBE)["id"]
            browser.open(daemon.url + "/#/")
            self.assertTrue(browser.until("!document.getElementById('token-bar').hidden"))
            self.assertFalse(browser.js("document.querySelector('#jobs tr[data-id]') !== null"))  # nothing without it
            time.sleep(3)  # a few refreshes fail meanwhile: one error line, not one per refresh
            self.assertEqual(browser.js("document.querySelectorAll('#main .error').length"), 1)
            browser.js("""document.getElementById('token').value = 's3cret-ada';
                          document.getElementById('token-form').requestSubmit()""")
            self.assertIn(browser.until(f"(document.querySelector('#jobs tr[data-id=\"{job}\"] .status') || {{}}).textContent"),
                          ("queued", "running", "succeeded"))
            self.assertTrue(browser.js("document.getElementById('token-bar').hidden"))
            # Kept: a reload lists the job without asking again.
            browser.open(daemon.url + "/#/")
            browser.until(f"document.querySelector('#jobs tr[data-id=\"{job}\"]') !== null")
            self.assertTrue(browser.js("document.getElementById('token-bar').hidden"))
        finally:
            browser.close()
            daemon.stop()
            shutil.rmtree(directory, ignore_errors=True)


sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
import skip_aware  # noqa: E402  (tests/skip_aware.py)


if __name__ == "__main__":
    skip_aware.main(verbosity=2)
