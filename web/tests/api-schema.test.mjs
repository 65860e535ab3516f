// The API's types in one place: docs/api.schema.json. Checks that the TypeScript client's types
// (web/src/api.ts) have the same names, fields, optionality and types as the schema's $defs, that
// docs/API.md documents exactly the schema's endpoints, names their fields and shows no other,
// and that a live `matlas demo` answers every endpoint as the schema says (requests validated too).
//
//   MATLAS_BIN=../build/matlas node --test tests/api-schema.test.mjs
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { mkdtempSync, readdirSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { probePoints } from "./probe-points.mjs";
import { documentedEndpoints, normalSchema, normalTs, schema, validate } from "./schema.mjs";
import { startDemo, webDir, stopServer } from "./server.mjs";
import { importTs } from "./transpile.mjs";

const def = (name) => ({ $ref: `#/$defs/${name}` });

test("the TypeScript client's types are the schema's", () => {
  const tsTypes = normalTs(join(webDir, "src", "api.ts"));
  for (const [name, node] of Object.entries(schema.$defs)) {
    assert.ok(tsTypes[name], `web/src/api.ts has no type ${name}`);
    assert.deepEqual(tsTypes[name], normalSchema(node), `web/src/api.ts: ${name} differs from docs/api.schema.json`);
  }
});

test("docs/API.md documents exactly the schema's endpoints and their fields", () => {
  const docs = documentedEndpoints(join(webDir, "..", "docs", "API.md"));
  const key = (e) => `${e.method} ${e.path} -> ${e.type}`;
  assert.deepEqual(docs.map(key).sort(), schema.endpoints.map((e) => key({ ...e, type: e.response.type })).sort());
  for (const e of schema.endpoints) {
    const text = docs.find((d) => d.method === e.method && d.path === e.path).text;
    const fields = [e.request, e.response.schema].filter((s) => s?.$ref).flatMap(topFields);
    for (const f of fields) assert.match(text, new RegExp(`\\b${f}\\b`), `docs/API.md, ${e.method} ${e.path}: no "${f}"`);
    // And the other way: every JSON key the section shows is a field of its request or answer.
    const known = new Set([e.request, e.response.schema].filter((s) => s?.$ref).flatMap((s) => fieldNames(s)));
    // Keys are "key": value, or listed without values: {"index", "name", "weight"}.
    const keys = [...text.matchAll(/"([a-z_]+)"\s*:/g)].map((m) => m[1]);
    for (const [, list] of text.matchAll(/\{("[a-z_]+"(?:\s*,\s*"[a-z_]+")+)\s*\}/g))
      keys.push(...list.split(",").map((k) => k.trim().slice(1, -1)));
    for (const key of keys) assert.ok(known.has(key), `docs/API.md, ${e.method} ${e.path}: "${key}" is not in the schema`);
  }
});

/** The top-level property names of a schema node (of every alternative of a union). */
function topFields(node) {
  if (node.$ref) return topFields(schema.$defs[node.$ref.replace("#/$defs/", "")]);
  if (node.anyOf) return [...new Set(node.anyOf.flatMap(topFields))];
  return Object.keys(node.properties ?? {});
}

/** Every property name reachable from a schema node. */
function fieldNames(node, seen = new Set()) {
  if (node.$ref) {
    if (seen.has(node.$ref)) return [];
    seen.add(node.$ref);
    return fieldNames(schema.$defs[node.$ref.replace("#/$defs/", "")], seen);
  }
  const children = [...Object.values(node.properties ?? {}), ...(node.anyOf ?? []), ...(node.prefixItems ?? []),
    ...(typeof node.items === "object" ? [node.items] : [])];
  return [...Object.keys(node.properties ?? {}), ...children.flatMap((c) => fieldNames(c, seen))];
}

test("the validator rejects what the schema forbids", () => {
  const good = { index: 1, name: "a", weight: 0.5 };
  assert.deepEqual(validate(good, def("TopWeight")), []);
  assert.equal(validate({ ...good, index: 1.5 }, def("TopWeight")).length, 1);
  assert.equal(validate({ ...good, extra: 1 }, def("TopWeight")).length, 1);
  assert.equal(validate({ index: 1, name: "a" }, def("TopWeight")).length, 1);
  assert.equal(validate([1, 2], def("Rgb")).length, 1);
  assert.deepEqual(validate(null, schema.$defs.ProjectReply.properties.nearest), []);
});

let work, server, url;
before(async () => {
  work = mkdtempSync(join(tmpdir(), "matlas-api-"));
  ({ url, server } = await startDemo(work));
});
after(async () => {
  await stopServer(server);
  rmSync(work, { recursive: true, force: true });
});

/** Calls an endpoint of the schema with `body` (validated against its request schema). */
async function call(method, path, body, contentType = "application/json") {
  const bare = `/${path.split("?")[0]}`;
  const e = schema.endpoints.find((x) => x.method === method && new RegExp(`^${x.path.replace("INDEX", "\\d+").replace("NAME", "[A-Za-z0-9_.-]+")}$`).test(bare));
  assert.ok(e, `${method} ${path} is in the schema`);
  if (e.request?.$ref) assert.deepEqual(validate(body, e.request), [], `request to ${path}`);
  const init = body === undefined ? {} : {
    method, headers: { "Content-Type": contentType }, body: contentType === "application/json" ? JSON.stringify(body) : body,
  };
  const res = await fetch(new URL(path, url), init);
  return { res, e };
}

async function expectAnswer(method, path, body, contentType) {
  const { res, e } = await call(method, path, body, contentType);
  assert.equal(res.status, 200, `${path}: ${res.status}`);
  assert.equal(res.headers.get("content-type").split(";")[0], e.response.type, `${path}: content type`);
  if (e.response.schema) {
    const json = await res.json();
    assert.deepEqual(validate(json, e.response.schema), [], `${path}: answer`);
    return json;
  }
  const bytes = Buffer.from(await res.arrayBuffer());
  if (e.response.type === "image/png") assert.equal(bytes.subarray(1, 4).toString(), "PNG", `${path}: a PNG`);
  return bytes;
}

test("a live server answers every endpoint as the schema says", async () => {
  const model = await expectAnswer("GET", "api/model");
  const x = model.latent[1];
  await expectAnswer("POST", "api/preview", { x, env: model.scenes.default_env, object: model.scenes.default_object, size: 64 });
  const status = await expectAnswer("GET", `api/preview/status?env=${model.scenes.default_env}&object=${model.scenes.default_object}`);
  assert.equal(status.ready, true, "the default scene is prepared before serving");
  await expectAnswer("POST", "api/preview/refine", { x, env: model.scenes.default_env, object: model.scenes.default_object, seconds: 0.1 });
  await expectAnswer("POST", "api/gi/refine", { x, scene: model.gi.scenes[1], seconds: 0.05, exposure: "auto", tone: "aces" });
  await expectAnswer("GET", `api/thumbnail/2?env=${model.scenes.default_env}&object=${model.scenes.default_object}&size=32`);
  const w = await expectAnswer("POST", "api/weights", { x, top: 4 });
  assert.equal(w.weights.length, model.count);
  const table = await expectAnswer("POST", "api/export", { x });
  assert.equal(table.readInt32LE(0), model.dims[0]);
  const bsdf = await expectAnswer("POST", "api/export", { x, material: 1, format: "bsdf" });
  assert.equal(bsdf.subarray(0, 12).toString("latin1"), "tensor_file\0", "an RGL tensor file");
  const spectral = await expectAnswer("POST", "api/export", { x, material: 1, format: "bsdf-spectral" });
  assert.equal(spectral.subarray(0, 12).toString("latin1"), "tensor_file\0", "an RGL tensor file");
  assert.ok(spectral.includes("wavelengths") && spectral.includes("spectra"), "with its spectra");
  const fit = await expectAnswer("POST", "api/fit", { x, material: 1 });
  assert.equal(fit.name, model.names[1]);
  const mtlx = await expectAnswer("POST", "api/fit/file", { x, material: 1, format: "mtlx" });
  assert.match(mtlx.toString(), /<open_pbr_surface /);
  await expectAnswer("POST", "api/slice", { x, phi_d: 45 });
  await expectAnswer("POST", "api/lobe", { x, theta_i: 20, samples: 31 });
  const albedo = await expectAnswer("POST", "api/albedo", { x });
  assert.equal(albedo.theta_o.length, model.albedo_angles);
  await expectAnswer("POST", "api/map", { layer: "variance", axes: [0, 1], x, rect: [model.bounds.min[0], model.bounds.max[0],
    model.bounds.min[1], model.bounds.max[1]], size: [8, 8] });
  const cache = join(work, "cache");
  const db = join(cache, readdirSync(cache).find((d) => d.startsWith("demo-db-")));
  const projected = await expectAnswer("POST", "api/project", readFileSync(join(db, `${model.names[2]}.binary`)),
    "application/octet-stream");
  assert.equal(projected.nearest.index, 2);
  // Sparse samples: a fresh plan, and a fit of samples read off material 2's lobe.
  const plan = await expectAnswer("POST", "api/sample-plan?k=4", "", "text/csv");
  assert.equal(plan.directions.length, 4);
  const lobe = await expectAnswer("POST", "api/lobe", { x: model.latent[2], theta_i: 30, samples: 19 });
  const rows = lobe.theta_o.map((to, j) => [30, 180, Math.abs(to), to >= 0 ? 0 : 180, ...lobe.rgb[j]])
    .filter((r) => r[2] < 80 && r.slice(4).every((v) => v > 0));
  const fitted = await expectAnswer("POST", "api/fit-samples",
    ["theta_i,phi_i,theta_o,phi_o,r,g,b", ...rows.map((r) => r.join(","))].join("\n"), "text/csv");
  assert.equal(fitted.used, rows.length);
  assert.equal(fitted.covariance.length, model.dim);
  // The real-time viewer's data: shapes agree with the payloads.
  const rt = await expectAnswer("GET", "api/realtime");
  // Per view angle: the (L + 1)(L + 2)/2 rotated-ZH terms, then one weight per sharp lobe.
  const lobes = rt.coefficients - ((rt.bands + 1) * (rt.bands + 2)) / 2;
  assert.ok(lobes >= 0 && lobes <= 8, `${lobes} lobe weights`);
  assert.equal(rt.materials, model.count);
  const coefficients = await expectAnswer("GET", "api/realtime/coefficients");
  assert.equal(coefficients.length, 4 * (model.count + 1) * rt.theta_o_count * rt.coefficients * 3);
  const env = rt.environments[0];
  const { res: envRes } = await call("GET", `api/realtime/environment/${env}`);
  const shape = JSON.parse(envRes.headers.get("x-matlas-shape"));
  // The band maps, then the detail atlas: one map per lobe and the background.
  const bandFloats = (shape.bands + 1) * shape.width * shape.height * 3;
  assert.equal(shape.detail.offset, bandFloats);
  assert.equal(shape.detail.lobes.length, lobes);
  assert.equal(shape.detail.layers, lobes + 1);
  // Then the direct lights: direction and power per light.
  assert.equal(shape.lights.offset, bandFloats + shape.detail.layers * shape.detail.width * shape.detail.height * 3);
  assert.equal((await envRes.arrayBuffer()).byteLength, 4 * (shape.lights.offset + 6 * shape.lights.count));
  const lightTable = await expectAnswer("POST", "api/realtime/lights", { x });
  const { theta_h, theta_d, phi_d } = rt.light_table;
  assert.equal(lightTable.length, 2 * 3 * theta_h * theta_d * phi_d);
  const mesh = rt.objects.find((o) => o !== "sphere");
  if (mesh) {
    const bytes = await expectAnswer("GET", `api/realtime/mesh/${mesh}`);
    const v = bytes.readUInt32LE(0), t = bytes.readUInt32LE(4);
    assert.equal(bytes.length, 8 + 4 * (6 * v + 3 * t));
  }
  await expectAnswer("POST", "api/realtime/reference", { x, env, rotation: 30, exposure: 0, size: 32 });
  const radiance = await expectAnswer("POST", "api/realtime/reference/radiance", { x, env, rotation: 30, exposure: 0, size: 32 });
  assert.equal(radiance.length, 4 * 4 * 32 * 32);
  const values = new Float32Array(radiance.buffer, radiance.byteOffset, radiance.length / 4);
  assert.ok(values.some((v, i) => i % 4 === 3 && v === 1) && values.every((v) => Number.isFinite(v)));
});

test("the page's local weights (web/src/local-weights.ts) are the server's", async (t) => {
  const { LocalWeights } = (await importTs(["local-weights"]))["local-weights"];
  const model = await expectAnswer("GET", "api/model");
  const data = await expectAnswer("GET", "api/interpolation");
  assert.equal(data.mode, model.interpolation);
  const local = new LocalWeights(data);
  // The materials, midpoints of pairs of them, and points spread over the whole domain.
  const points = probePoints(model, 60, 5);
  let projected = 0, largest = 0;
  for (const x of points) {
    const server = (await expectAnswer("POST", "api/weights", { x, top: 1 })).weights;
    const w = local.weights(x);
    assert.equal(w.length, server.length);
    const gp = local.gp(x), sum = gp.reduce((a, b) => a + b, 0);
    if (gp.some((v) => v + (1 - sum) / gp.length < 0)) ++projected;
    for (let i = 0; i < w.length; ++i) largest = Math.max(largest, Math.abs(w[i] - server[i]));
  }
  t.diagnostic(`${points.length} points, ${projected} projected onto the simplex; largest difference ${largest.toExponential(2)}`);
  assert.ok(largest < 1e-9, `largest difference from the server's weights: ${largest}`);
  if (data.mode === "convex") assert.ok(projected >= 10 && projected < points.length, `${projected} of ${points.length} projected`);
});

test("errors are the schema's error object", async () => {
  const { res } = await call("POST", "api/weights", { x: [1e9, 0] });
  assert.equal(res.status, 400);
  const body = await res.json();
  assert.deepEqual(validate(body, schema.errors.schema), []);
  assert.match(body.error, /x\[0\]/);
  // The scene view: an unknown scene (400) and a scene being traced (503) answer the error object.
  const model = await (await fetch(new URL("api/model", url))).json();
  const x = model.latent[0].join(",");
  const { res: unknown } = await call("GET", `api/gi?scene=attic&x=${x}`);
  assert.equal(unknown.status, 400);
  assert.deepEqual(validate(await unknown.json(), schema.errors.schema), []);
  const { res: tracing } = await call("GET", `api/gi?scene=${model.gi.scenes[0]}&x=${x}`);
  assert.equal(tracing.status, 503);
  const body503 = await tracing.json();
  assert.deepEqual(validate(body503, schema.errors.schema), []);
  assert.match(body503.error, /being prepared/);
});
