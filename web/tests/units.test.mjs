// Unit tests of the page's plumbing, without a browser or server: the typed store, LatestOnly
// (latest input only, abort on supersede), DragThrottle (at most every ms while dragging, the
// drag's last point always sent), retryWhileBusy (503 backoff) and the page's interpolation
// weights (local-weights.ts) against their defining equations. The TypeScript
// modules are transpiled with the TypeScript compiler into a temporary folder and imported.
import { test } from "node:test";
import assert from "node:assert/strict";
import { importTs } from "./transpile.mjs";
import { isolationAllPairs, placeLabelsAllPairs } from "./label_reference.mjs";

const modules = await importTs(["api", "store", "latest", "drag-throttle", "retry", "local-weights"]);
const { Store } = modules.store;
const { LatestOnly } = modules.latest;
const { DragThrottle } = modules["drag-throttle"];
const { retryWhileBusy } = modules.retry;
const { ApiError } = modules.api;
const { LocalWeights } = modules["local-weights"];

test("Store.update calls each listener of the changed keys once", () => {
  const store = new Store({ env: "a", object: "b", x: [0] });
  const calls = [];
  store.on(["env", "object"], (s) => calls.push(`${s.env}/${s.object}`));
  store.on(["x"], () => calls.push("x"));
  store.update({ env: "c", object: "d" });
  assert.deepEqual(calls, ["c/d"], "one call for both fields, with both already set");
  store.update({ x: [1] });
  assert.deepEqual(calls, ["c/d", "x"]);
});

test("Store.on returns what removes the listener, also from inside an update", () => {
  const store = new Store({ x: 0 });
  const calls = [];
  const off = store.on(["x"], (s) => {
    calls.push(`first ${s.x}`);
    off();  // removes itself while the store calls its listeners
  });
  store.on(["x"], (s) => calls.push(`second ${s.x}`));
  store.update({ x: 1 });
  assert.deepEqual(calls, ["first 1", "second 1"], "the listener after a removed one is still called");
  store.update({ x: 2 });
  assert.deepEqual(calls, ["first 1", "second 1", "second 2"], "a removed listener is not called again");
  off();  // twice: nothing happens
  store.update({ x: 3 });
  assert.equal(calls.length, 4);
});

const deferred = () => {
  let resolve;
  const promise = new Promise((r) => (resolve = r));
  return { promise, resolve };
};

test("LatestOnly runs the latest input only and drops a superseded result", async () => {
  const started = [], done = [], gates = [];
  const latest = new LatestOnly(async (input, signal) => {
    started.push(input);
    const g = deferred();
    gates.push(g);
    signal.addEventListener("abort", () => g.resolve(`aborted ${input}`));
    return g.promise;
  }, (result, input) => done.push([input, result]));
  latest.request(1);
  latest.request(2);
  latest.request(3);
  assert.deepEqual(started, [1], "one task in flight");
  gates[0].resolve("r1");
  await new Promise((r) => setTimeout(r, 0));
  assert.deepEqual(started, [1, 3], "then the latest input, 2 skipped");
  latest.request(4, 0, true);
  await new Promise((r) => setTimeout(r, 0));
  assert.deepEqual(started, [1, 3, 4], "a superseding request aborts the one in flight");
  gates[2].resolve("r4");
  await new Promise((r) => setTimeout(r, 0));
  assert.deepEqual(done, [[1, "r1"], [4, "r4"]], "the aborted task's result is dropped");
  assert.equal(latest.busy, false);
});

test("LatestOnly says when it is idle: after the latest input, not between inputs", async () => {
  const gates = [];
  let idle = 0;
  const latest = new LatestOnly(async (input, signal) => {
    const g = deferred();
    gates.push(g);
    signal.addEventListener("abort", () => g.resolve(`aborted ${input}`));
    return g.promise;
  }, () => {}, () => {}, () => idle++);
  latest.request(1);
  latest.request(2, 0, true);  // aborts 1; 2 runs next
  await new Promise((r) => setTimeout(r, 0));
  assert.equal(idle, 0, "not idle while the superseding input runs");
  assert.equal(gates.length, 2);
  gates[1].resolve("r2");
  await new Promise((r) => setTimeout(r, 0));
  assert.equal(idle, 1, "idle once the latest input is done");
  assert.equal(latest.busy, false);
});

test("DragThrottle sends at rest at once, and while dragging at most every interval with the latest point last", async () => {
  let clock = 1000;
  const sent = [];
  const throttle = new DragThrottle(40, (x) => sent.push([x, clock]), () => clock);
  throttle.request("a", false);
  throttle.request("b", false);
  assert.deepEqual(sent.map((s) => s[0]), ["a", "b"], "at rest every request goes at once");
  clock += 50;
  throttle.request("c", true);  // 50 ms after the last send: at once
  clock += 10;
  throttle.request("d", true);  // 10 ms after: held
  clock += 10;
  throttle.request("e", true);  // replaces d
  assert.deepEqual(sent.map((s) => s[0]), ["a", "b", "c"], "within the interval nothing more is sent");
  await new Promise((r) => setTimeout(r, 60));  // the trailing call: 20 ms of the interval were left
  assert.deepEqual(sent.map((s) => s[0]), ["a", "b", "c", "e"], "the latest held point follows once, d never");
  clock += 5;
  throttle.request("f", true);  // 5 ms after e's send: held again
  throttle.request("g", false);  // the drag ends: at once, and the held one is dropped
  await new Promise((r) => setTimeout(r, 60));
  assert.deepEqual(sent.map((s) => s[0]), ["a", "b", "c", "e", "g"]);
});

test("retryWhileBusy retries 503 with growing delays, and only 503", async () => {
  const waits = [];
  let calls = 0;
  const result = await retryWhileBusy(async () => {
    if (++calls < 4) throw new ApiError(503, "the preview scene is being prepared");
    return "image";
  }, { firstDelayMs: 5, maxDelayMs: 12, onWait: (w) => waits.push(w) });
  assert.equal(result, "image");
  assert.deepEqual(waits.map((w) => w.attempts), [1, 2, 3]);
  assert.deepEqual(waits.map((w) => w.delayMs), [5, 8, 12], "x1.6, capped");
  assert.match(waits[0].message, /being prepared/);
  await assert.rejects(retryWhileBusy(async () => { throw new ApiError(400, "bad x"); }), /bad x/);
  const controller = new AbortController();
  const pending = retryWhileBusy(async () => { throw new ApiError(503, "busy"); },
    { signal: controller.signal, firstDelayMs: 10_000 });
  controller.abort(new DOMException("superseded", "AbortError"));
  await assert.rejects(pending, { name: "AbortError" });
});

/** A small interpolation problem: n points in q dimensions, K and its factor computed here. */
function problem(n, q, seed, mode = "gp") {
  let state = seed;
  const random = () => ((state = (state * 1103515245 + 12345) % 2147483648) / 2147483648);
  const latent = Array.from({ length: n }, () => Array.from({ length: q }, () => 2 * random() - 1));
  const nugget = 1e-4, l = 1;
  const K = latent.map((a, i) => latent.map((b, j) => Math.exp(-a.reduce((s, v, d) => s + (v - b[d]) ** 2, 0) / (l * l)) + (i === j ? nugget : 0)));
  const L = K.map(() => new Array(n).fill(0));
  for (let j = 0; j < n; ++j)
    for (let i = j; i < n; ++i) {
      let s = K[i][j];
      for (let k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = i === j ? Math.sqrt(s) : s / L[j][j];
    }
  const taper = latent.map((a, i) => Math.min(0.1 * l, ...latent.filter((_, j) => j !== i).map((b) => 0.5 * Math.hypot(...a.map((v, d) => v - b[d])))));
  // An SPD metric: B B^T / n + ridge.
  const B = latent.map(() => Array.from({ length: n }, () => random() - 0.5));
  const metric = B.flatMap((a, i) => B.map((b, j) => a.reduce((s, v, k) => s + v * b[k], 0) / n + (i === j ? 0.01 : 0)));
  return { data: { mode, lengthscale: l, nugget, latent, taper_radius: taper, cholesky: L.flat(), metric }, K, random };
}

test("LocalWeights.gp solves K w = k(x) and reproduces the data points", () => {
  const { data, K, random } = problem(12, 3, 7);
  const lw = new LocalWeights(data);
  for (let i = 0; i < 12; ++i) {
    const w = lw.gp(data.latent[i]);
    w.forEach((v, j) => assert.ok(Math.abs(v - (i === j ? 1 : 0)) < 1e-9, `w(x_${i})[${j}] = ${v}`));
  }
  for (let t = 0; t < 20; ++t) {
    const x = [0, 0, 0].map(() => 3 * random() - 1.5);
    const w = lw.gp(x);
    // k(x) from the definition (x is never inside a taper here, so no nugget term).
    for (let i = 0; i < 12; ++i) {
      const k = Math.exp(-data.latent[i].reduce((s, v, d) => s + (v - x[d]) ** 2, 0));
      const Kw = K[i].reduce((s, v, j) => s + v * w[j], 0);
      assert.ok(Math.abs(Kw - k) < 1e-10, `(K w - k)_${i} = ${Kw - k}`);
    }
  }
  assert.throws(() => lw.gp([0, 0]), /2 coordinates, the model has q = 3/);
});

test("LocalWeights.convex is the metric projection onto the simplex (its optimality conditions hold)", () => {
  const n = 10;
  const { data, random } = problem(n, 2, 11, "convex");
  const lw = new LocalWeights(data);
  const A = (i, j) => data.metric[i * n + j];
  let projected = 0;
  for (let t = 0; t < 200; ++t) {
    const w = Float64Array.from({ length: n }, () => 3 * (random() - 0.5));
    const c = lw.convex(w);
    const sw = w.reduce((a, b) => a + b, 0);
    const g = Array.from(w, (v) => v + (1 - sw) / n);
    assert.ok(Math.abs(c.reduce((a, b) => a + b, 0) - 1) < 1e-12);
    assert.ok(c.every((v) => v >= 0));
    if (g.every((v) => v >= 0)) {
      g.forEach((v, i) => assert.ok(Math.abs(c[i] - v) < 1e-12));
      continue;
    }
    ++projected;
    // KKT: the gradient A (c - g) equals nu on the support and is at least nu off it.
    const grad = Array.from({ length: n }, (_, i) => c.reduce((s, v, j) => s + A(i, j) * (v - g[j]), 0));
    const support = [...c.keys()].filter((i) => c[i] > 1e-14);
    const nu = grad[support[0]];
    for (const i of support) assert.ok(Math.abs(grad[i] - nu) < 1e-9, `gradient on the support: ${grad[i]} vs ${nu}`);
    for (let i = 0; i < n; ++i) if (!support.includes(i)) assert.ok(grad[i] >= nu - 1e-9, `bound ${i}: ${grad[i]} < ${nu}`);
  }
  assert.ok(projected > 100, `only ${projected} of 200 points needed the projection`);
  assert.deepEqual(Array.from(new LocalWeights({ ...data, mode: "gp" }).weights(data.latent[3])).map((v) => Math.round(v) + 0),
    Array.from({ length: n }, (_, i) => (i === 3 ? 1 : 0)));
});

// The map's label declutter (labels.ts): the grid-bucketed placement and the sweep for isolation
// give exactly what the all-pairs definitions give, at n = 1000 too.
const labelsModule = (await importTs(["labels"])).labels;
const { placeLabels, isolation } = labelsModule;

test("placeLabels and isolation equal their all-pairs definitions (n up to 1000)", () => {
  let seed = 31;
  const u = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  for (const n of [0, 1, 2, 50, 1000]) {
    const W = 900, H = 640;
    const xs = [], ys = [], labels = [];
    for (let i = 0; i < n; i++) {
      const kind = i % 4;
      let x = kind === 0 ? 300 + 30 * u() : -8 + (W + 16) * u();
      let y = kind === 0 ? 200 + 30 * u() : -8 + (H + 16) * u();
      if (kind === 3 && i > 4) [x, y] = [xs[i - 4], ys[i - 4]];
      xs.push(x);
      ys.push(y);
      labels.push({ x, y, width: 20 + 140 * u(), height: 15, priority: 0 });
    }
    const p = isolation(xs, ys);
    assert.deepEqual(p, isolationAllPairs(xs, ys), `isolation, n = ${n}`);
    labels.forEach((l, i) => (l.priority = p[i]));
    const a = placeLabels(labels, W, H, 7), b = placeLabelsAllPairs(labels, W, H, 7, labelsModule);
    assert.deepEqual(a, b, `placement, n = ${n}`);
    if (n >= 50) assert.ok(a.filter((box) => box).length > n / 20);
  }
  const q = isolation([0, 3, NaN, 10, 10], [0, 4, 1, 0, NaN]);
  assert.equal(q[0], 5);
  assert.equal(q[2], Infinity);
});
