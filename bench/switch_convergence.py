#!/usr/bin/env python3
"""After a switch to a preview scene the server has not prepared: the time until the point's
refined preview converges (its estimated error at most 1 %), while the server prepares the
scene's basis in the background. The page's order (web/src/preview.ts): a status poll starts the
preparation, then refinements of 0.4 s each (denoised), one after the other.

    python3 bench/switch_convergence.py URL ENV:MATERIAL [ENV:MATERIAL ...]

Each pair is a switch to ENV (on the sphere) at MATERIAL's latent point; start the server with
another default environment (`matlas serve MODEL --env city --cache EMPTY_DIR`) so that the
first switch to an environment finds it unprepared. Prints the first image's time and the time
to 1 % (or gives up after 120 s).
"""
import json
import sys
import time
import urllib.request

url, pairs = sys.argv[1].rstrip("/"), [a.split(":", 1) for a in sys.argv[2:]]
model = json.load(urllib.request.urlopen(url + "/api/model"))
for env, name in pairs:
    x = model["latent"][model["names"].index(name)]
    t0 = time.time()
    urllib.request.urlopen(f"{url}/api/preview/status?env={env}&object=sphere").read()
    first = None
    while True:
        body = json.dumps({"x": x, "env": env, "object": "sphere", "seconds": 0.4, "denoise": True}).encode()
        reply = urllib.request.urlopen(urllib.request.Request(url + "/api/preview/refine", body,
                                                              {"Content-Type": "application/json"}))
        reply.read()
        spp = int(reply.headers.get("X-Matlas-Spp", "0"))
        error = reply.headers.get("X-Matlas-Error", "unknown")
        t = time.time() - t0
        if spp > 0 and first is None:
            first = t
        if error != "unknown" and float(error) <= 0.01:
            print(f"{env} {name}: first image {first:.2f} s, error <= 1 % after {t:.1f} s ({spp} spp, "
                  f"{100 * float(error):.2f} %)")
            break
        if t > 120:
            print(f"{env} {name}: not at 1 % after {t:.0f} s ({spp} spp, {error})")
            break
