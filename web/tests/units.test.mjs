// Unit tests of the page's plumbing, without a browser or server: the typed store, LatestOnly
// (latest input only, abort on supersede) and retryWhileBusy (503 backoff). The TypeScript
// modules are transpiled with the TypeScript compiler into a temporary folder and imported.
import { test, after } from "node:test";
import assert from "node:assert/strict";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import ts from "typescript";
import { webDir } from "./server.mjs";

const out = mkdtempSync(join(tmpdir(), "matlas-units-"));
after(() => rmSync(out, { recursive: true, force: true }));
for (const name of ["api", "store", "latest", "retry"]) {
  const source = readFileSync(join(webDir, "src", `${name}.ts`), "utf8");
  const js = ts.transpileModule(source, { compilerOptions: { module: ts.ModuleKind.ES2022, target: ts.ScriptTarget.ES2022 } })
    .outputText.replace(/from "\.\/(\w+)"/g, 'from "./$1.js"');
  writeFileSync(join(out, `${name}.js`), js);
}
const { Store } = await import(join(out, "store.js"));
const { LatestOnly } = await import(join(out, "latest.js"));
const { retryWhileBusy } = await import(join(out, "retry.js"));
const { ApiError } = await import(join(out, "api.js"));

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
