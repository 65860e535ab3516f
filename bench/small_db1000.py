#!/usr/bin/python3
"""A 1000-material database on a small grid, for timing what grows with n and not with the table
size (convex weights, map layers, the latent placement): 9 x 9 x 18 bins (every 10th theta_h,
theta_d and phi_d bin of the MERL grid, 35 KB per file). The tables of SRC whose names start
with neither ggx nor synth (69 of /tmp/db100) subsampled, plus random convex mixtures of 2 or 3
of them up to 1000 (seed 1000; -1 where any part is unmeasured).
Standard library only. Usage: bench/small_db1000.py SRC OUT"""
import array, os, random, struct, sys
src, out = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
TH, TD, PD = 90, 90, 180
sub = [(h, d, p) for h in range(0, TH, 10) for d in range(0, TD, 10) for p in range(0, PD, 10)]
names = sorted(f for f in os.listdir(src) if f.endswith('.binary') and not f.startswith('ggx') and not f.startswith('synth'))
tables = []
for f in names:
    a = array.array('d')
    with open(os.path.join(src, f), 'rb') as fh:
        dims = struct.unpack('<3i', fh.read(12))
        a.fromfile(fh, dims[0] * dims[1] * dims[2] * 3)
    n = TH * TD * PD
    vals = []
    for c in range(3):
        for (h, d, p) in sub:
            vals.append(a[c * n + (h * TD + d) * PD + p])
    tables.append((f[:-7], vals))
def write(name, vals):
    with open(os.path.join(out, name + '.binary'), 'wb') as fh:
        fh.write(struct.pack('<3i', 9, 9, 18))
        array.array('d', vals).tofile(fh)
for name, vals in tables: write(name, vals)
rng = random.Random(1000)
for k in range(1000 - len(tables)):
    m = rng.choice([2, 3]); picks = rng.sample(range(len(tables)), m)
    w = [rng.expovariate(1.0) for _ in picks]; s = sum(w); w = [x / s for x in w]
    vals = []
    for i in range(len(tables[0][1])):
        vs = [tables[p][1][i] for p in picks]
        vals.append(-1.0 if any(v < 0 for v in vs) else sum(wi * v for wi, v in zip(w, vs)))
    write('mix-%04d' % k, vals)
print(len(tables), 'tables of', src, 'and', 1000 - len(tables), 'mixtures')
