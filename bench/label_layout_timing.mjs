// The map's label declutter per redraw (web/src/labels.ts: isolation + placeLabels, run on every
// draw of the map) against the all-pairs definitions it replaced, at n = 100 and 1000 random
// markers on a 900 x 640 canvas, alternated in one run.
//   node bench/label_layout_timing.mjs   (from the repository root; needs web/node_modules)
import { importTs } from "../web/tests/transpile.mjs";

const { placeLabels, isolation, overlaps } = (await importTs(["labels"])).labels;

function placeLabelsAllPairs(labels, width, height, r, gap = 3) {
  const out = labels.map(() => null);
  const order = labels.map((_, i) => i).sort((a, b) => labels[b].priority - labels[a].priority || a - b);
  const markers = labels.map((l) => ({ x0: l.x - r, y0: l.y - r, x1: l.x + r, y1: l.y + r }));
  const placed = [];
  const off = r + gap, d = 0.7 * off;
  for (const i of order) {
    const l = labels[i];
    const candidates = [
      { x0: l.x + off, y0: l.y - l.height / 2, x1: l.x + off + l.width, y1: l.y + l.height / 2 },
      { x0: l.x - off - l.width, y0: l.y - l.height / 2, x1: l.x - off, y1: l.y + l.height / 2 },
      { x0: l.x - l.width / 2, y0: l.y - off - l.height, x1: l.x + l.width / 2, y1: l.y - off },
      { x0: l.x - l.width / 2, y0: l.y + off, x1: l.x + l.width / 2, y1: l.y + off + l.height },
      { x0: l.x + d, y0: l.y - d - l.height, x1: l.x + d + l.width, y1: l.y - d },
      { x0: l.x + d, y0: l.y + d, x1: l.x + d + l.width, y1: l.y + d + l.height },
      { x0: l.x - d - l.width, y0: l.y - d - l.height, x1: l.x - d, y1: l.y - d },
      { x0: l.x - d - l.width, y0: l.y + d, x1: l.x - d, y1: l.y + d + l.height },
    ];
    for (const c of candidates) {
      if (c.x0 < 0 || c.y0 < 0 || c.x1 > width || c.y1 > height) continue;
      if (placed.some((p) => overlaps(c, p))) continue;
      if (markers.some((m, k) => k !== i && overlaps(c, m))) continue;
      out[i] = c;
      placed.push(c);
      break;
    }
  }
  return out;
}

function isolationAllPairs(xs, ys) {
  return xs.map((x, i) => {
    let d = Infinity;
    for (let j = 0; j < xs.length; j++) if (j !== i) d = Math.min(d, Math.hypot(x - xs[j], ys[i] - ys[j]));
    return d;
  });
}

let seed = 5;
const u = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
for (const n of [100, 1000]) {
  const W = 900, H = 640, xs = [], ys = [], labels = [];
  for (let i = 0; i < n; i++) {
    const x = W * u(), y = H * u();
    xs.push(x);
    ys.push(y);
    labels.push({ x, y, width: 40 + 80 * u(), height: 15, priority: 0 });
  }
  const redraw = (iso, place) => () => {
    const p = iso(xs, ys);
    labels.forEach((l, i) => (l.priority = p[i]));
    return place(labels, W, H, 7);
  };
  const before = redraw(isolationAllPairs, placeLabelsAllPairs), after = redraw(isolation, placeLabels);
  const t = [0, 0];
  before(), after();
  for (let r = 0; r < 20; r++)
    [before, after].forEach((f, k) => {
      const t0 = performance.now();
      f();
      t[k] += performance.now() - t0;
    });
  console.log(`n = ${n}: all pairs ${(t[0] / 20).toFixed(2)} ms, grid and sweep ${(t[1] / 20).toFixed(2)} ms per redraw ` +
    `(${(t[0] / t[1]).toFixed(1)}x)`);
}
