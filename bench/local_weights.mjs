// The page's interpolation weights (web/src/local-weights.ts) against a running `matlas serve`:
// at every material, the midpoints of consecutive materials and 300 points spread over the
// domain, the largest difference from POST /api/weights, how many points went through the convex
// projection, and the time per point in node (three passes over all points).
//
//   node bench/local_weights.mjs http://127.0.0.1:8080/
import { probePoints } from "../web/tests/probe-points.mjs";
import { importTs } from "../web/tests/transpile.mjs";

const { LocalWeights } = (await importTs(["local-weights"]))["local-weights"];
const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const model = await (await fetch(new URL("api/model", url))).json();
const data = await (await fetch(new URL("api/interpolation", url))).json();
const local = new LocalWeights(data);

const points = probePoints(model, 300, 9);

let largest = 0, projected = 0;
for (const x of points) {
  const res = await fetch(new URL("api/weights", url), {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ x, top: 1 }),
  });
  const server = (await res.json()).weights;
  const w = local.weights(x);
  for (let i = 0; i < w.length; ++i) largest = Math.max(largest, Math.abs(w[i] - server[i]));
  const gp = local.gp(x), sum = gp.reduce((a, b) => a + b, 0);
  if (gp.some((v) => v + (1 - sum) / gp.length < 0)) ++projected;
}
console.log(`${model.name}: n = ${model.count}, mode ${data.mode}, ${points.length} points, ${projected} projected; ` +
  `largest difference from the server's weights ${largest.toExponential(2)}`);
for (let pass = 0; pass < 3; ++pass) {
  const start = performance.now();
  for (const x of points) local.weights(x);
  console.log(`pass ${pass + 1}: ${((performance.now() - start) / points.length).toFixed(3)} ms per point`);
}
