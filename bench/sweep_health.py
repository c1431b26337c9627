#!/usr/bin/python3
"""Does a large sweep hold the server? (issue 25, point 3; bench/README.md, "A large sweep and health").

    /usr/bin/python3 bench/sweep_health.py [build/granulabd] [--points N] [--spec-kb K]

Starts a fresh granulabd (a real SQLite file in a temp folder, one worker, no speed probe), then posts one
sweep of N points (default 1000, the most a sweep may have) of a crystal spec padded to about K KB (default
15: N x K stays under the default --max-sweep-mb 16) by a knock-out list, while another thread asks
GET /v1/health every 5 ms on its own keep-alive connection. Prints the sweep's answer time and the health
latencies seen meanwhile (median, 99th percentile, most). Standard library only.
"""
import http.client
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARGS = sys.argv[1:]
POSITIONAL = [a for i, a in enumerate(ARGS) if not a.startswith("--") and (i == 0 or not ARGS[i - 1].startswith("--"))]
DAEMON = POSITIONAL[0] if POSITIONAL else os.path.join(ROOT, "build", "granulabd")
POINTS = int(ARGS[ARGS.index("--points") + 1]) if "--points" in ARGS else 1000
SPEC_KB = float(ARGS[ARGS.index("--spec-kb") + 1]) if "--spec-kb" in ARGS else 15


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main():
    folder = tempfile.mkdtemp(prefix="granulab-sweep-health-")
    port = free_port()
    log = open(os.path.join(folder, "log"), "w")
    daemon = subprocess.Popen([DAEMON, "--port", str(port), "--db", os.path.join(folder, "g.db"),
                               "--speed-probe-seconds", "0"], stdout=log, stderr=subprocess.STDOUT)
    try:
        for _ in range(200):
            try:
                http.client.HTTPConnection("127.0.0.1", port, timeout=2).request("GET", "/v1/health")
                break
            except OSError:
                time.sleep(0.05)
        # A crystal big enough for a long knock-out list; the list pads the spec to about SPEC_KB.
        knockout, base = [], None
        while True:
            base = {"experiment": "crystal_compression", "grain": {"edge_spheres": 2},
                    "crystal": {"grains_x": 20, "rows_z": 20, "layers_y": 10, "knockout": knockout},
                    "loading": {"max_strain": 1e-3}}
            if len(json.dumps(base)) >= SPEC_KB * 1000:
                break
            knockout = list(range(len(knockout) + 200))
        body = json.dumps({"spec": base, "vary": {"loading.confining_pressure": [1000 + i for i in range(POINTS)]}})
        latencies, stop = [], threading.Event()

        def probe():
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
            while not stop.is_set():
                start = time.perf_counter()
                connection.request("GET", "/v1/health")
                connection.getresponse().read()
                latencies.append(time.perf_counter() - start)
                time.sleep(0.005)
            connection.close()

        prober = threading.Thread(target=probe)
        prober.start()
        time.sleep(0.3)  # a baseline before the sweep
        before = len(latencies)
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
        start = time.perf_counter()
        connection.request("POST", "/v1/sweeps", body, {"Content-Type": "application/json"})
        answer = connection.getresponse()
        text = answer.read()
        took = time.perf_counter() - start
        during = latencies[before:]
        stop.set()
        prober.join()
        if answer.status != 201:
            sys.exit("the sweep was refused: %d %s" % (answer.status, text[:300]))
        during.sort()
        ms = lambda s: "%.1f ms" % (1e3 * s)
        print("sweep of %d points, %.1f KB spec (%.1f MB of specs stored): 201 in %s" % (POINTS, len(json.dumps(base)) / 1e3,
                                                                         POINTS * len(json.dumps(base)) / 1e6, ms(took)))
        print("health during it: %d answers, median %s, 99th percentile %s, most %s" % (
            len(during), ms(during[len(during) // 2]), ms(during[int(0.99 * (len(during) - 1))]), ms(during[-1])))
    finally:
        daemon.terminate()
        daemon.wait(timeout=30)
        log.close()
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
