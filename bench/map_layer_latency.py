#!/usr/bin/env python3
"""End-to-end time of POST /api/map (a map layer, as the browser asks for it) against `matlas serve`,
for several binaries (for instance the commits before and after a change), alternated ROUNDS times
so that they share the machine's noise.

    bench/map_layer_latency.py MODEL ROUNDS BINARY... [--size 128] [--layers albedo,variance,plausibility]

Each binary serves MODEL on its own port (one cache folder for all, so that the preview basis is
rendered once, before any timing); the request is the browser's first one: axes 0 and 1 through
the latent mean, the latent points' box plus a tenth of its larger side on every side, size x size
cells. Prints per binary and layer the minimum and median wall time over the rounds, the server
process's CPU time per request (user + system from /proc, 10 ms ticks: what the machine's load
does not change much), the load average, and whether the PNGs of all binaries are byte-identical.
Python standard library only.
"""
import argparse
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(url, body=None, timeout=600):
    data = json.dumps(body).encode() if body is not None else None
    req = urllib.request.Request(url, data=data, headers={"Content-Type": "application/json"} if data else {})
    with urllib.request.urlopen(req, timeout=timeout) as r:
        return r.read()


def cpu_seconds(pid):
    """User + system CPU time of a process so far (all its threads)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def wait_ready(base, x, deadline_s=900):
    """Until /api/model answers and a preview is served (the basis rendered or loaded)."""
    end = time.time() + deadline_s
    while time.time() < end:
        try:
            request(base + "api/model", timeout=5)
            request(base + "api/preview", {"x": x}, timeout=600)
            return
        except (urllib.error.URLError, ConnectionError, TimeoutError):
            time.sleep(1)
    raise SystemExit(f"{base}: not ready after {deadline_s} s")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("model")
    p.add_argument("rounds", type=int)
    p.add_argument("binaries", nargs="+")
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--layers", default="albedo,variance,plausibility")
    a = p.parse_args()
    layers = a.layers.split(",")
    cache = tempfile.mkdtemp(prefix="matlas-map-bench-")
    servers = []
    try:
        body = None
        for binary in a.binaries:
            port = free_port()
            proc = subprocess.Popen([binary, "serve", a.model, "--port", str(port), "--cache", cache,
                                     "--gi-scenes", "none"],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            base = f"http://127.0.0.1:{port}/"
            servers.append((binary, proc, base))
            if body is None:
                for _ in range(600):
                    try:
                        model = json.loads(request(base + "api/model", timeout=5))
                        break
                    except (urllib.error.URLError, ConnectionError):
                        time.sleep(0.5)
                lo, hi = model["bounds"]["min"], model["bounds"]["max"]
                x = [(l + h) / 2 for l, h in zip(lo, hi)]
                pad = 0.1 * max(hi[0] - lo[0], hi[1] - lo[1])
                rect = [lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad]
                body = {"axes": [0, 1], "x": x, "rect": rect, "size": [a.size, a.size]}
                print(f"model {a.model}: n = {model['count']}, q = {model['dim']}, "
                      f"interpolation {model.get('interpolation')}; rect {[round(v, 4) for v in rect]}")
            wait_ready(base, body["x"])  # one at a time: the first renders the basis, the others load it
        times = {(b, l): [] for b, _, _ in servers for l in layers}
        cpu = {(b, l): [] for b, _, _ in servers for l in layers}
        pngs = {}
        loads = []
        for r in range(a.rounds):
            for layer in layers:
                for binary, proc, base in servers:
                    loads.append(os.getloadavg()[0])
                    c0 = cpu_seconds(proc.pid)
                    t0 = time.perf_counter()
                    png = request(base + "api/map", dict(body, layer=layer))
                    times[(binary, layer)].append(time.perf_counter() - t0)
                    cpu[(binary, layer)].append(cpu_seconds(proc.pid) - c0)
                    pngs.setdefault((binary, layer), png)
                    time.sleep(0.2)
        print(f"load average during the runs: {min(loads):.2f} .. {max(loads):.2f}; "
              f"{os.cpu_count()} cores; {time.strftime('%Y-%m-%d %H:%M %Z')}")
        for layer in layers:
            for binary, _, _ in servers:
                t = times[(binary, layer)]
                c = cpu[(binary, layer)]
                print(f"{layer:13s} {binary}: min {1e3 * min(t):8.1f} ms, median {1e3 * statistics.median(t):8.1f} ms "
                      f"({len(t)} requests); server CPU {1e3 * statistics.mean(c):8.1f} ms per request (mean)")
            same = len({pngs[(b, layer)] for b, _, _ in servers}) == 1
            print(f"{layer:13s} PNGs byte-identical across binaries: {same}")
    finally:
        for _, proc, _ in servers:
            proc.send_signal(signal.SIGTERM)
        for _, proc, _ in servers:
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
        subprocess.run(["rm", "-rf", cache])


if __name__ == "__main__":
    sys.exit(main())
