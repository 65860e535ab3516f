// Unit tests of the designer's tools' plain logic (issue 26), without a browser or server: the
// view in the address bar (url-state.ts) keeps only what is valid for the model, the slice's
// colour-bar ticks (slice-plot.ts) and the markers' fading with the distance from the slice
// (map-draw.ts).
import { test } from "node:test";
import assert from "node:assert/strict";
import { importTs } from "./transpile.mjs";

const modules = await importTs(["url-state", "slice-plot", "map-draw", "labels", "map-geometry"]);
const { readUrlView } = modules["url-state"];
const { logTicks, scalePosition } = modules["slice-plot"];
const { sliceAlpha } = modules["map-draw"];

const model = {
  dim: 2, count: 3, names: ["a", "b", "c"], latent: [[0, 0], [1, 1], [-1, 0.5]],
  domain: { min: [-2, -2], max: [2, 2] }, bounds: { min: [-1, 0], max: [1, 1] },
  scenes: { envs: ["studio", "sky"], objects: ["sphere", "bunny"], default_env: "studio", default_object: "sphere" },
  layers: ["albedo", "variance", "plausibility"],
};

test("the address bar's view keeps what is valid for the model", () => {
  const v = readUrlView(model, "#x=0.5,9&env=sky&object=teapot&layer=variance&view=0.1,0.2,3&list=1;0.25_-0.5;7;x");
  assert.deepEqual(v.x, [0.5, 2], "x clamped to the domain");
  assert.equal(v.env, "sky");
  assert.equal(v.object, undefined, "an object the server does not offer is ignored");
  assert.equal(v.layer, "variance");
  assert.deepEqual(v.view, { cx: 0.1, cy: 0.2, half: 3 });
  assert.deepEqual(v.list.map((it) => [it.name, it.index, it.x]),
    [["b", 1, [1, 1]], ["point (0.250, -0.500)", null, [0.25, -0.5]]], "index 7 and 'x' dropped");
  assert.deepEqual(readUrlView(model, "#x=1&axes=0,0&view=0,0,-1&layer=nonsense"), {}, "wrong lengths, equal axes, a negative zoom");
  assert.deepEqual(readUrlView({ ...model, dim: 3 }, "#axes=2,0").axes, [2, 0]);
});

test("the slice's colour bar: 0 and decades up to the maximum, on the server's log curve", () => {
  assert.deepEqual(logTicks(0.5), [0, 0.01, 0.1]);
  assert.deepEqual(logTicks(150), [0, 0.01, 0.1, 1, 10, 100]);
  const many = logTicks(5e4);
  assert.ok(many.length <= 6 && many[0] === 0 && many.at(-1) === 1e4, `${many}`);
  assert.equal(scalePosition(0, 10), 0);
  assert.ok(Math.abs(scalePosition(10, 10) - 1) < 1e-12);
  // log(1 + f / 0.01) / log(1 + max / 0.01), as POST /api/slice encodes values.
  assert.ok(Math.abs(scalePosition(1, 10) - Math.log(101) / Math.log(1001)) < 1e-12);
});

test("markers fade with the distance of their other coordinates from the current point's", () => {
  const bounds = { min: [0, 0, 0, 0], max: [1, 1, 2, 4] };
  assert.equal(sliceAlpha([0.3, 0.9, 1, 2], [0.5, 0.5, 1, 2], [0, 1], bounds), 1, "on the slice: opaque, whatever its own axes");
  // Other coordinates 2 and 3, scaled by the extents 2 and 4: d = hypot(0.3 / 2, 0.8 / 4) = 0.25.
  const a = sliceAlpha([0, 0, 1.3, 2.8], [0, 0, 1, 2], [0, 1], bounds);
  assert.ok(Math.abs(a - (0.1 + 0.9 * Math.exp(-((0.25 / 0.15) ** 2)))) < 1e-12, `${a}`);
  assert.ok(sliceAlpha([0, 0, 2, 4], [0, 0, 0, 0], [0, 1], bounds) < 0.1 + 1e-9, "far: at the floor");
});
