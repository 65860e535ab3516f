// The map's label declutter per redraw (web/src/labels.ts: isolation + placeLabels, run on every
// draw of the map) against the all-pairs definitions it replaced, at n = 100 and 1000 random
// markers on a 900 x 640 canvas, alternated in one run.
//   node bench/label_layout_timing.mjs   (from the repository root; needs web/node_modules)
import { importTs } from "../web/tests/transpile.mjs";
import { isolationAllPairs, placeLabelsAllPairs } from "../web/tests/label_reference.mjs";

const labelsModule = (await importTs(["labels"])).labels;
const { placeLabels, isolation } = labelsModule;

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
  const before = redraw(isolationAllPairs, (...a) => placeLabelsAllPairs(...a, labelsModule)), after = redraw(isolation, placeLabels);
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
