// Browser tests of the material browser: Debian's Chromium (headless) driven by playwright-core,
// against `matlas demo` on a small synthetic database (16x16x32 grid) on an ephemeral port.
//
//   MATLAS_BIN=../build/matlas node --test tests/
//
// Checks: the page loads; a click on the map updates the preview, which equals the server's image
// for that point; dragging streams previews (latencies are printed); export downloads a valid MERL
// table of the current point; uploading a database file projects it next to its latent point; the
// path tool fills its strip; shift+drag and alt+arrows pan the map; the plausibility line and layer;
// drawn labels never overlap (fitted and zoomed in) and a hidden one shows on hover; the
// interpolation badge says the model's mode; the albedo layer is transparent far from the data; a
// map layer on its way keeps the previous one and shows that it is loading, and a newer layer
// aborts the request of the stale one.
// Scene switching (issue #12): a scene being prepared is retried with progress shown, a stale
// error disappears after a later success, environment and object changed together render that one
// combination, a newer scene supersedes one still being prepared, and the tooltip falls back to
// the default scene's thumbnails while the chosen one is prepared.
// Screenshots go to test-results/ (browser.png, map-zoomed.png, scene-*.png, error-*.png).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, mkdirSync, rmSync, readdirSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

import { bin, openPage, startDemo, webDir as here, stopServer } from "./server.mjs";

const work = mkdtempSync(join(tmpdir(), "matlas-browser-"));
const results = join(here, "test-results");
mkdirSync(results, { recursive: true });

let server, url, context, page;

async function api(path, body) {
  const res = await fetch(new URL(path, url), body === undefined ? {} : {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  });
  assert.equal(res.status, 200, `${path}: ${res.status}`);
  return Buffer.from(await res.arrayBuffer());
}

/** Bytes of the image shown by an <img> (a blob: URL) in the page. */
async function imageBytes(selector) {
  const b64 = await page.$eval(selector, async (img) => {
    const buf = new Uint8Array(await (await fetch(img.src)).arrayBuffer());
    let s = "";
    for (const v of buf) s += String.fromCharCode(v);
    return btoa(s);
  });
  return Buffer.from(b64, "base64");
}

/** Waits until the preview shows the full-size image of the current point. */
async function settled() {
  await page.waitForFunction(() => {
    const m = window.matlas;
    return m && m.shown && m.shown.size === m.model.preview.size &&
      JSON.stringify(m.shown.x) === JSON.stringify(m.x);
  }, null, { timeout: 20_000 });
}

before(async () => {
  ({ url, server } = await startDemo(work));
  ({ context, page } = await openPage(work, url, { acceptDownloads: true }));
});

after(async () => {
  await context?.close();
  await stopServer(server);
  rmSync(work, { recursive: true, force: true });
});

test("the page loads the model and shows a preview", async () => {
  const info = await page.textContent("#model-info");
  assert.match(info, /materials · q = 2/);
  const count = await page.evaluate(() => window.matlas.model.count);
  assert.ok(count >= 20, `demo catalogue has ${count} materials`);
});

test("a click on the map shows the server's image of that point", async () => {
  await settled();
  const before = await imageBytes("#preview");
  const box = await page.locator("#map").boundingBox();
  await page.mouse.click(box.x + box.width * 0.37, box.y + box.height * 0.58);
  await settled();
  const state = await page.evaluate(() => ({ x: window.matlas.x, env: window.matlas.env, object: window.matlas.object, size: window.matlas.model.preview.size }));
  const shown = await imageBytes("#preview");
  assert.notDeepEqual(shown, before, "the preview changed");
  const expected = await api("api/preview", { x: state.x, env: state.env, object: state.object, size: state.size });
  assert.deepEqual(shown, expected, "the preview is the server's image for the clicked point");
});

test("dragging streams previews with one request in flight", async () => {
  const box = await page.locator("#map").boundingBox();
  const n0 = await page.evaluate(() => window.matlas.previews);
  await page.evaluate(() => (window.matlas.latencies.length = 0));
  await page.mouse.move(box.x + box.width * 0.3, box.y + box.height * 0.5);
  await page.mouse.down();
  for (let k = 0; k <= 40; k++) {
    await page.mouse.move(box.x + box.width * (0.3 + 0.01 * k), box.y + box.height * (0.5 - 0.005 * k));
    await page.waitForTimeout(16);
  }
  await page.mouse.up();
  await settled();
  const lat = (await page.evaluate(() => window.matlas.latencies)).slice().sort((a, b) => a - b);
  const n1 = await page.evaluate(() => window.matlas.previews);
  assert.ok(n1 - n0 >= 5, `previews during the drag: ${n1 - n0}`);
  const q = (p) => lat[Math.min(lat.length - 1, Math.floor(p * lat.length))];
  console.log(`drag: ${lat.length} previews, pointer-to-image latency median ${q(0.5).toFixed(1)} ms, p90 ${q(0.9).toFixed(1)} ms, max ${lat[lat.length - 1].toFixed(1)} ms`);
});

test("at rest the preview refines: more samples, less error, over the basis image", async () => {
  const box = await page.locator("#map").boundingBox();
  await page.mouse.click(box.x + box.width * 0.45, box.y + box.height * 0.4);
  await settled();
  const basis = await imageBytes("#preview");
  await page.waitForFunction(() => window.matlas.refined && window.matlas.refined.error !== null, null, { timeout: 30_000 });
  const first = await page.evaluate(() => ({ ...window.matlas.refined }));
  assert.deepEqual(first.x, await page.evaluate(() => window.matlas.x), "the refined image is of the current point");
  assert.ok(await page.locator("#preview-refined").isVisible(), "the refined image is shown");
  assert.match(await page.textContent("#preview-refine"), /(refining|converged) · \d+ spp · ±[\d.]+ %/);
  await page.waitForFunction((spp) => window.matlas.refined && (window.matlas.refined.converged ||
    window.matlas.refined.spp >= 4 * spp), first.spp, { timeout: 60_000 });
  const later = await page.evaluate(() => ({ ...window.matlas.refined }));
  assert.ok(later.spp > first.spp, `samples grew: ${first.spp} -> ${later.spp}`);
  assert.ok(later.error < first.error, `the estimated error fell: ${first.error} -> ${later.error}`);
  assert.deepEqual(await imageBytes("#preview"), basis, "the basis image underneath is unchanged (never mixed)");
  assert.notDeepEqual(await imageBytes("#preview-refined"), basis);
  await page.locator(".preview-card").screenshot({ path: join(results, "preview-refined.png") });
  console.log(`refinement: ${first.spp} spp ±${(100 * first.error).toFixed(2)} % -> ${later.spp} spp ±${(100 * later.error).toFixed(2)} %`);
});

test("the refined preview is denoised by default, labelled so, and the toggle shows the plain mean", async () => {
  const bodies = [];
  const onRequest = (r) => r.url().endsWith("/api/preview/refine") && bodies.push(JSON.parse(r.postData()));
  page.on("request", onRequest);
  try {
    await page.waitForFunction(() => window.matlas.refined && window.matlas.refined.denoised, null, { timeout: 30_000 });
    assert.match(await page.textContent("#preview-refine"), /^denoised · (refining|converged) · \d+ spp/);
    const toggle = page.locator("#preview-denoise");
    assert.ok(await toggle.isVisible(), "the toggle shows over the refined image");
    assert.equal(await toggle.getAttribute("aria-pressed"), "true");
    assert.ok(bodies.every((b) => b.denoise === true), "every refinement asked for the denoised image");
    const denoised = await imageBytes("#preview-refined");
    await toggle.click();
    await page.waitForFunction(() => window.matlas.refined && !window.matlas.refined.denoised, null, { timeout: 30_000 });
    assert.equal(await toggle.getAttribute("aria-pressed"), "false");
    assert.doesNotMatch(await page.textContent("#preview-refine"), /denoised/);
    assert.equal(bodies[bodies.length - 1].denoise, false, "the plain mean is asked for");
    assert.notDeepEqual(await imageBytes("#preview-refined"), denoised, "the plain mean differs from the denoised image");
    await page.locator("#preview-denoise").click();
    await page.waitForFunction(() => window.matlas.refined && window.matlas.refined.denoised, null, { timeout: 30_000 });
    assert.equal(bodies[bodies.length - 1].denoise, true, "back on: the denoised image is asked for again");
  } finally {
    page.off("request", onRequest);
  }
});

test("a drag drops the refined image and sends no refinement while the pointer moves", async () => {
  await page.waitForFunction(() => window.matlas.refined !== null, null, { timeout: 30_000 });
  const box = await page.locator("#map").boundingBox();
  const sent = [];
  const onRequest = (r) => r.url().endsWith("/api/preview/refine") && sent.push(performance.now());
  await page.mouse.move(box.x + box.width * 0.45, box.y + box.height * 0.4);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.47, box.y + box.height * 0.42);
  await page.waitForFunction(() => window.matlas.refined === null, null, { timeout: 5_000 });
  assert.ok(await page.locator("#preview-refined").isHidden(), "the refined image is gone at once");
  page.on("request", onRequest);
  for (let k = 0; k <= 20; k++) {
    await page.mouse.move(box.x + box.width * (0.47 + 0.005 * k), box.y + box.height * 0.42);
    await page.waitForTimeout(20);
  }
  page.off("request", onRequest);
  assert.equal(sent.length, 0, "no refinement requested during the drag");
  await page.mouse.up();
  await settled();
  await page.waitForFunction(() => window.matlas.refined !== null, null, { timeout: 30_000 });
  assert.deepEqual(await page.evaluate(() => window.matlas.refined.x), await page.evaluate(() => window.matlas.x),
    "after the drag the new point refines");
});

test("shift+drag and alt+arrows pan the map without moving the current point", async () => {
  const box = await page.locator("#map").boundingBox();
  const where = () => page.evaluate(() => ({ p: window.matlas.map.materialClientPosition(0), x: window.matlas.x.slice() }));
  const a = await where();
  const [sx, sy] = [box.x + box.width * 0.5, box.y + box.height * 0.5];
  await page.keyboard.down("Shift");
  await page.mouse.move(sx, sy);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) await page.mouse.move(sx + 6 * k, sy - 4 * k);
  await page.mouse.up();
  await page.keyboard.up("Shift");
  const b = await where();
  assert.ok(Math.abs(b.p[0] - a.p[0] - 60) < 1 && Math.abs(b.p[1] - a.p[1] + 40) < 1,
    `material 0 moved with the pointer: ${JSON.stringify(a.p)} -> ${JSON.stringify(b.p)}`);
  assert.deepEqual(b.x, a.x, "panning does not move the current point");
  await page.locator("#map").focus();
  await page.keyboard.press("Alt+ArrowRight");
  const c = await where();
  assert.ok(Math.abs(c.p[0] - b.p[0] + 0.1 * box.width) < 1, `alt+right pans by a tenth: ${b.p[0]} -> ${c.p[0]}`);
  await page.keyboard.press("0");  // back to the fitted view for the tests that follow
});

test("the plausibility line and map layer describe the current point", async () => {
  // At a database material the point is plausible.
  const [mx, my] = await page.evaluate(() => window.matlas.map.materialClientPosition(1));
  await page.mouse.click(mx, my);
  await settled();
  // The panels of this point (not those of the previous one, still shown under load).
  await page.waitForFunction(() => {
    const m = window.matlas;
    return m.lastWeights && JSON.stringify(m.lastWeights.x) === JSON.stringify(m.x);
  }, null, { timeout: 10_000 });
  const line = await page.textContent("#plausibility");
  assert.match(line, /^physically plausible: albedo/, line);
  const layer = page.waitForResponse((r) => r.url().endsWith("/api/map") && r.request().postData().includes("plausibility"));
  await page.selectOption("#layer", "plausibility");
  assert.equal((await layer).status(), 200);
  // The legend says what the layer can show: nothing to find over plausible inputs mixed convexly;
  // otherwise red, and under convex weights the albedo layer's "no data here" far from the data.
  const model = JSON.parse((await api("/api/model")).toString());
  assert.equal(typeof model.plausible_everywhere, "boolean");
  const legend = await page.textContent("#legend-layer");
  assert.match(legend, model.plausible_everywhere ? /every point is plausible/ : /not physically plausible/, legend);
  if (model.interpolation === "convex") assert.match(legend, /no data here/, legend);
  else assert.doesNotMatch(legend, /no data here/, legend);
  await page.selectOption("#layer", "albedo");
});

test("a map layer on its way keeps the previous one, says it is loading, and a newer one aborts it", async () => {
  await page.waitForFunction(() => window.matlas.map.layer !== null, null, { timeout: 20_000 });
  // The layer the previous test asked for (debounced by 120 ms) has arrived: none is on its way.
  await page.waitForTimeout(300);
  await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
  const shown = await page.evaluate(() => window.matlas.map.layer.rect);
  // Hold every layer response until released.
  let release;
  const held = new Promise((r) => (release = r));
  const asked = [], failed = [];
  await page.route("**/api/map", async (route) => {
    asked.push(JSON.parse(route.request().postData()).layer);
    await held;
    await route.continue().catch(() => {});  // the page may have aborted it meanwhile
  });
  const onFailed = (r) => r.url().endsWith("/api/map") && failed.push(r.failure()?.errorText);
  page.on("requestfailed", onFailed);
  try {
    await page.selectOption("#layer", "variance");
    await page.waitForSelector("#map-wrap.layer-loading", { timeout: 5_000 });
    assert.equal(await page.getAttribute("#map-wrap", "aria-busy"), "true");
    assert.deepEqual(await page.evaluate(() => window.matlas.map.layer?.rect), shown, "the previous layer stays");
    await page.selectOption("#layer", "plausibility");
    for (let t = 0; asked.length < 2 && t < 100; ++t) await page.waitForTimeout(50);
    assert.deepEqual(asked, ["variance", "plausibility"]);
    release();
    await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
    assert.equal(await page.getAttribute("#map-wrap", "aria-busy"), "false");
    assert.equal(failed.length, 1, `the stale request is aborted: ${failed}`);
    assert.ok(await page.evaluate(() => window.matlas.map.layer !== null));
  } finally {
    release();
    page.off("requestfailed", onFailed);
    await page.unroute("**/api/map");
    await page.selectOption("#layer", "albedo");
  }
});

test("a slow map layer shows a coarse one at once, then the full one over it", async () => {
  await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
  // As if the last layer had been slow (a large model): every layer now comes coarse first.
  // The last full layer took 2 s: the coarse one is sized to take a quarter of that (32 cells wide).
  await page.evaluate(() => { window.matlas.layerTiming.coarseAfterMs = -1; window.matlas.layerTiming.lastMs = { variance: 2000 }; });
  let release;
  const held = new Promise((r) => (release = r));
  const widths = [];
  await page.route("**/api/map", async (route) => {
    const width = JSON.parse(route.request().postData()).size[0];
    widths.push(width);
    if (width === 128) await held;  // the full layer waits until released
    await route.continue().catch(() => {});
  });
  try {
    const before = await page.evaluate(() => window.matlas.layerTiming.coarseShown);
    await page.selectOption("#layer", "variance");
    await page.waitForFunction((b) => window.matlas.layerTiming.coarseShown > b, before, { timeout: 10_000 });
    assert.equal(await page.evaluate(() => window.matlas.map.layer.image.width), 32, "the coarse layer is shown");
    assert.equal(await page.getAttribute("#map-wrap", "aria-busy"), "true", "and the full one is still coming");
    release();
    await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
    assert.equal(await page.evaluate(() => window.matlas.map.layer.image.width), 128, "the full layer replaces it");
    assert.deepEqual(widths, [32, 128]);
  } finally {
    release();
    await page.unroute("**/api/map");
    await page.evaluate(() => { window.matlas.layerTiming.coarseAfterMs = 1200; window.matlas.layerTiming.lastMs = {}; });
    await page.selectOption("#layer", "albedo");
  }
});

test("a kind of layer not shown yet is expected to take as long as the others: slow ones make it coarse first", async () => {
  await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
  // The albedo layer took 2 s, no plausibility layer has come yet: it comes coarse first (32
  // cells wide, as after its own 2 s layer), though the demo's few materials alone would not ask
  // for a coarse one; a variance layer's time says nothing of the others'.
  const widths = [];
  const onRequest = (r) => r.url().endsWith("/api/map") && widths.push(JSON.parse(r.postData()).size[0]);
  const change = async (kind, lastMs) => {
    await page.selectOption("#layer", "none");
    await page.evaluate((lastMs) => { window.matlas.layerTiming.lastMs = lastMs; }, lastMs);
    widths.length = 0;
    await page.selectOption("#layer", kind);
    await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
    return [...widths];
  };
  page.on("request", onRequest);
  try {
    assert.deepEqual(await change("plausibility", { albedo: 2000 }), [32, 128], "coarse first after a slow albedo layer");
    assert.deepEqual(await change("plausibility", { variance: 2000 }), [128], "a slow variance layer says nothing of it");
    assert.deepEqual(await change("variance", { albedo: 2000 }), [32, 128], "a variance layer goes by the others too");
    assert.deepEqual(await change("plausibility", { albedo: 2000, plausibility: 300 }), [128], "its own time first");
  } finally {
    page.off("request", onRequest);
    await page.evaluate(() => { window.matlas.layerTiming.lastMs = {}; });
    await page.selectOption("#layer", "albedo");
    await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
  }
});

test("the refinement at rest waits while a map layer is on its way, then goes on", async () => {
  await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
  let release;
  const held = new Promise((r) => (release = r));
  await page.route("**/api/map", async (route) => {
    await held;
    await route.continue().catch(() => {});
  });
  const sent = [];
  const onRequest = (r) => r.url().endsWith("/api/preview/refine") && sent.push(JSON.parse(r.postData()).x);
  try {
    await page.selectOption("#layer", "variance");
    await page.waitForSelector("#map-wrap.layer-loading", { timeout: 5_000 });
    await page.waitForTimeout(600);  // a refinement pass already in flight ends (0.4 s each)
    page.on("request", onRequest);
    // A new point while the layer is held: its preview shows, its refinement waits.
    const box = await page.locator("#map").boundingBox();
    await page.mouse.click(box.x + box.width * 0.41, box.y + box.height * 0.47);
    await page.waitForTimeout(1500);
    assert.equal(sent.length, 0, "no refinement asked while the layer is on its way");
    const x = await page.evaluate(() => window.matlas.x);
    const refined = page.waitForRequest((r) => r.url().endsWith("/api/preview/refine"), { timeout: 10_000 });
    release();
    await refined;
    assert.deepEqual(sent[0], x, "once the layer came, the new point refines");
  } finally {
    release();
    page.off("request", onRequest);
    await page.unroute("**/api/map");
    await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 20_000 });
    await page.selectOption("#layer", "albedo");
  }
});

test("export downloads the MERL table of the current point", async () => {
  const x = await page.evaluate(() => window.matlas.x);
  if (await page.isHidden("#download-menu")) await page.click("#download-open");
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#export-binary")]);
  const path = join(work, "download.binary");
  await download.saveAs(path);
  const bytes = readFileSync(path);
  const dims = [bytes.readInt32LE(0), bytes.readInt32LE(4), bytes.readInt32LE(8)];
  assert.deepEqual(dims, [16, 16, 32]);
  assert.equal(bytes.length, 12 + 3 * 16 * 16 * 32 * 8);
  const values = new Float64Array(bytes.buffer.slice(bytes.byteOffset + 12, bytes.byteOffset + bytes.length));
  assert.ok(values.every((v) => Number.isFinite(v) && (v >= 0 || v === -1)), "finite, non-negative or missing");
  assert.ok(values.some((v) => v > 0), "not all zero");
  const expected = await api("api/export", { x });
  assert.deepEqual(bytes, expected, "the download is the table of the current point");
});

test("the download menu shows each fit's error first; every download is the server's and the CLI's file", async () => {
  const { x, material, names } = await page.evaluate(() => {
    const m = window.matlas, i = m.model.latent.findIndex((p) => p.every((v, d) => Math.abs(v - m.x[d]) <= 1e-9 * (1 + Math.abs(v))));
    return { x: m.x, material: i < 0 ? null : i, names: m.model.names };
  });
  if (await page.isHidden("#download-menu")) await page.click("#download-open");
  assert.equal(await page.getAttribute("#download-open", "aria-expanded"), "true");
  // The analytic files wait for the fit, whose error is shown before they are offered.
  await page.waitForSelector("#download-menu[data-fit=ready]", { timeout: 60_000 });
  const which = material === null ? {} : { material };
  const report = JSON.parse((await api("api/fit", { x, ...which })).toString());
  const shown = await page.textContent("#fit-error");
  assert.match(shown, /^relative RMS \d+\.\d %, albedo within \d+\.\d %/);
  assert.ok(shown.includes(`${(100 * report.error.relative_rms).toFixed(1)} %`), `${shown} vs ${report.error.relative_rms}`);
  assert.ok(shown.includes(`${(100 * report.error.albedo_error).toFixed(1)} %`), `${shown} vs ${report.error.albedo_error}`);
  assert.equal(await page.isEnabled("#export-mtlx"), true);

  // The same files from the command line, for the same model, point or material.
  const models = join(work, "cache", "models");
  const modelFile = join(models, readdirSync(models).find((f) => f.endsWith(".matlas")));
  const point = material === null ? ["--at", x.map((v) => JSON.stringify(v)).join(",")] : ["--material", names[material]];
  const cli = join(work, "cli");
  mkdirSync(cli, { recursive: true });
  execFileSync(bin, ["export", modelFile, ...point, "-o", join(cli, "f.bsdf"), "--no-check"], { stdio: "pipe" });
  execFileSync(bin, ["export", modelFile, ...point, "--format", "bsdf-spectral", "-o", join(cli, "f.bsdf-spectral"), "--no-check"], { stdio: "pipe" });
  execFileSync(bin, ["fit", modelFile, ...point, "-o", join(cli, "f.gltf"), "-o", join(cli, "f.mtlx"), "-o", join(cli, "f.py")], { stdio: "pipe" });
  for (const format of ["bsdf", "bsdf-spectral", "mtlx", "gltf", "py"]) {
    const [download] = await Promise.all([page.waitForEvent("download"), page.click(`#export-${format}`)]);
    assert.ok(download.suggestedFilename().endsWith(format === "bsdf-spectral" ? ".bsdf" : `.${format}`), download.suggestedFilename());
    const bytes = readFileSync(await savedAs(download, `menu.${format}`));
    const table = format.startsWith("bsdf");
    const server = table ? await api("api/export", { x, ...which, format }) : await api("api/fit/file", { x, ...which, format });
    assert.deepEqual(bytes, server, `${format}: the download is the server's file`);
    assert.deepEqual(bytes, readFileSync(join(cli, `f.${format}`)), `${format}: the download is what matlas writes`);
  }
  // Then Blender 2.8-3.6's own Principled BSDF, fitted after the glTF model: its error shown, its
  // script the server's and the CLI's (`matlas fit --model principled-v1`).
  await page.waitForSelector("#download-menu[data-fit-v1=ready]", { timeout: 60_000 });
  const v1 = JSON.parse((await api("api/fit", { x, ...which, model: "principled-v1" })).toString());
  assert.equal(v1.kind, "principled-v1");
  const shownV1 = await page.textContent("#fit-error-v1");
  assert.ok(shownV1.includes(`relative RMS ${(100 * v1.error.relative_rms).toFixed(1)} %`), `${shownV1} vs ${v1.error.relative_rms}`);
  execFileSync(bin, ["fit", modelFile, ...point, "--model", "principled-v1", "-o", join(cli, "f-v1.py")], { stdio: "pipe" });
  const [scriptV1] = await Promise.all([page.waitForEvent("download"), page.click("#export-py-v1")]);
  assert.ok(scriptV1.suggestedFilename().endsWith(".py"), scriptV1.suggestedFilename());
  const bytesV1 = readFileSync(await savedAs(scriptV1, "menu-v1.py"));
  assert.deepEqual(bytesV1, await api("api/fit/file", { x, ...which, format: "py", model: "principled-v1" }), "py-v1: the server's file");
  assert.deepEqual(bytesV1, readFileSync(join(cli, "f-v1.py")), "py-v1: what matlas writes");
  assert.match(bytesV1.toString(), /bsdf\.distribution = 'GGX'/);
  await page.locator("#download-menu").screenshot({ path: join(results, "download-menu.png") });
  await page.keyboard.press("Escape");
  assert.equal(await page.isHidden("#download-menu"), true);
});

async function savedAs(download, name) {
  const path = join(work, name);
  await download.saveAs(path);
  return path;
}

test("uploading a .binary projects it next to its latent point", async () => {
  const cache = join(work, "cache");
  const db = join(cache, readdirSync(cache).find((d) => d.startsWith("demo-db-")));
  const model = await page.evaluate(() => window.matlas.model);
  const i = 3;
  await page.setInputFiles("#upload", join(db, `${model.names[i]}.binary`));
  await page.waitForFunction(() => window.matlas.projected !== null, null, { timeout: 30_000 });
  const projected = await page.evaluate(() => window.matlas.projected);
  for (let d = 0; d < 2; d++) {
    const extent = model.bounds.max[d] - model.bounds.min[d];
    assert.ok(Math.abs(projected.x[d] - model.latent[i][d]) < 0.02 * extent,
      `coordinate ${d}: ${projected.x[d]} vs ${model.latent[i][d]}`);
  }
  assert.ok(projected.residual < 0.05, `residual ${projected.residual}`);
  assert.match(await page.textContent("#status"), /residual/);
  await settled();
});

test("the path tool shows a strip of previews", async () => {
  await page.selectOption("#path-a", "0");
  await page.selectOption("#path-b", "5");
  await page.click("#path-go");
  await page.waitForFunction(() => [...document.querySelectorAll("#strip img")].length === 8 &&
    [...document.querySelectorAll("#strip img")].every((im) => im.src.startsWith("blob:") && im.complete), null,
    { timeout: 20_000 });
  await page.screenshot({ path: join(results, "browser.png"), fullPage: true });
});

/** Pairs of drawn label boxes that overlap (should be none), and the boxes. */
async function labelState() {
  return page.evaluate(() => {
    const m = window.matlas.map;
    const boxes = m.labelBoxes.map((l) => ({ index: l.index, ...l.box }));
    const bad = [];
    for (let i = 0; i < boxes.length; i++)
      for (let j = i + 1; j < boxes.length; j++) {
        const a = boxes[i], b = boxes[j];
        if (a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1) bad.push([a.index, b.index]);
      }
    return { boxes, bad, visible: m.visibleMaterials, count: window.matlas.model.count };
  });
}

test("the interpolation badge says the model's mode", async () => {
  const mode = await page.evaluate(() => window.matlas.model.interpolation);
  assert.equal(mode, "convex", "the demo model is built with the default, convex interpolation");
  const badge = page.locator("#interpolation");
  assert.ok(await badge.isVisible(), "badge visible");
  assert.match(await badge.textContent(), /interpolation: convex/);
  assert.equal(await badge.getAttribute("data-mode"), "convex");
  assert.match(await badge.getAttribute("title"), /non-negative/);
});

test("map labels never overlap; hidden ones show on hover and zooming in shows more", async () => {
  await page.keyboard.press("Escape");
  await page.locator("#map").focus();
  await page.keyboard.press("0");
  await page.waitForTimeout(100);
  const fitted = await labelState();
  assert.deepEqual(fitted.bad, [], `overlapping labels: ${JSON.stringify(fitted.bad)}`);
  assert.ok(fitted.boxes.length >= 5, `labels drawn: ${fitted.boxes.length} of ${fitted.count}`);
  assert.equal(fitted.visible, fitted.count, "the fitted view frames every material");
  const size = await page.evaluate(() => { const r = document.getElementById("map").getBoundingClientRect(); return [r.width, r.height]; });
  for (const b of fitted.boxes) assert.ok(b.x0 >= 0 && b.y0 >= 0 && b.x1 <= size[0] && b.y1 <= size[1], `label inside the canvas: ${JSON.stringify(b)}`);
  // The fitted view: every material inside the canvas, with a margin.
  const positions = await page.evaluate(() => window.matlas.model.latent.map((_, i) => window.matlas.map.materialClientPosition(i)));
  const box = await page.locator("#map").boundingBox();
  for (const [x, y] of positions) assert.ok(x > box.x + 0.05 * box.width && x < box.x + 0.95 * box.width && y > box.y + 0.05 * box.height && y < box.y + 0.95 * box.height, `material at ${x},${y} inside the margin`);
  // Zoom in around a material whose label is hidden (in a crowd), else around material 0.
  const shown = new Set(fitted.boxes.map((b) => b.index));
  const hidden = [...Array(fitted.count).keys()].find((i) => !shown.has(i));
  const [zx, zy] = positions[hidden ?? 0];
  if (hidden !== undefined) {
    // Hovering it draws its label (on a plate).
    await page.mouse.move(zx, zy);
    await page.waitForFunction((i) => window.matlas.map.hoverLabel?.index === i, hidden, { timeout: 5_000 });
    assert.match(await page.textContent("#label-count"), /labels shown/);
  }
  await page.mouse.move(zx, zy);
  for (let k = 0; k < 3; k++) await page.mouse.wheel(0, -300);
  await page.waitForTimeout(200);
  await page.mouse.move(box.x + 2, box.y + 2);  // no hover
  await page.waitForTimeout(100);
  const zoomed = await labelState();
  assert.deepEqual(zoomed.bad, [], `overlapping labels zoomed in: ${JSON.stringify(zoomed.bad)}`);
  assert.ok(zoomed.visible >= 1);
  const labelled = new Set(zoomed.boxes.map((b) => b.index));
  if (hidden !== undefined) {
    const revealed = [...labelled].filter((i) => !shown.has(i)).length;
    assert.ok(revealed > 0, `zooming in shows labels hidden before: ${zoomed.boxes.length} of ${zoomed.visible} visible labelled`);
  }
  console.log(`labels: fitted ${fitted.boxes.length} of ${fitted.count}, zoomed in ${zoomed.boxes.length} of ${zoomed.visible} visible`);
  await page.locator("#map").screenshot({ path: join(results, "map-zoomed.png") });
  await page.keyboard.press("0");
});

test("the albedo layer is transparent far from the data and the legend says why", async () => {
  const model = await page.evaluate(() => window.matlas.model);
  assert.deepEqual(model.uncertainty, { fade_from: 0.5, fade_to: 0.9 });
  // A rectangle in the corner of the domain, far from every material.
  const [lo0, lo1] = model.domain.min;
  const w0 = model.bounds.min[0] - lo0, w1 = model.bounds.min[1] - lo1;
  const png = await api("api/map", { layer: "albedo", axes: [0, 1], x: model.latent[0],
    rect: [lo0, lo0 + 0.2 * w0, lo1, lo1 + 0.2 * w1], size: [8, 8] });
  const alpha = await page.evaluate(async (b64) => {
    const blob = await (await fetch(`data:image/png;base64,${b64}`)).blob();
    const bmp = await createImageBitmap(blob, { premultiplyAlpha: "none" });
    const c = new OffscreenCanvas(bmp.width, bmp.height);
    const g = c.getContext("2d");
    g.drawImage(bmp, 0, 0);
    return Array.from(g.getImageData(0, 0, bmp.width, bmp.height).data.filter((_, i) => i % 4 === 3));
  }, png.toString("base64"));
  assert.equal(alpha.length, 64);
  assert.ok(Math.max(...alpha) < 20, `far corner alpha: ${Math.max(...alpha)}`);
  await page.selectOption("#layer", "albedo");
  assert.match(await page.textContent("#legend-layer"), /no data here/);
});

test("the crowd button frames at least half of the materials, labels still apart", async () => {
  await page.click("#core-view");
  await page.waitForTimeout(200);
  const s = await labelState();
  assert.ok(s.visible >= s.count / 2, `${s.visible} of ${s.count} visible`);
  assert.deepEqual(s.bad, []);
  await page.click("#reset-view");
  await page.waitForTimeout(100);
  assert.equal((await labelState()).visible, s.count, "fit shows every material again");
});

// --- scene switching (issue #12): retry with progress, stale errors, one combination ---

/** Waits until the preview shows the full-size image of the current point in scene env/object. */
async function settledIn(env, object) {
  await page.waitForFunction(([e, o]) => {
    const m = window.matlas;
    return m.env === e && m.object === o && m.shown && m.shown.env === e && m.shown.object === o &&
      m.shown.size === m.model.preview.size && JSON.stringify(m.shown.x) === JSON.stringify(m.x);
  }, [env, object], { timeout: 90_000 });
}

/** Checks that the preview is the server's image of the current point in the current scene. */
async function previewIsServers() {
  const s = await page.evaluate(() => ({ x: window.matlas.x, env: window.matlas.env, object: window.matlas.object, size: window.matlas.model.preview.size }));
  assert.deepEqual(await imageBytes("#preview"), await api("api/preview", s), `the preview is the server's image in ${s.env}/${s.object}`);
}

/** The (env, object) of every preview request the page sends from now on. */
function recordPreviewRequests() {
  const seen = [];
  const onRequest = (r) => {
    if (r.url().endsWith("/api/preview")) {
      const b = JSON.parse(r.postData());
      seen.push(`${b.env}/${b.object}`);
    }
  };
  page.on("request", onRequest);
  return { seen, stop: () => page.off("request", onRequest) };
}

test("a scene being prepared shows its progress and a first image of the point, then appears, without 503s", async () => {
  const { envs, default_object: object } = await page.evaluate(() => window.matlas.model.scenes);
  assert.ok(envs.length >= 3, `environments: ${envs}`);
  const statuses = [], polls = [];
  const onResponse = (r) => {
    if (r.url().endsWith("/api/preview")) statuses.push(r.status());
    if (r.url().includes("/api/preview/status")) polls.push(r.status());
  };
  const consoleErrors = [];
  const onConsole = (m) => m.type() === "error" && consoleErrors.push(m.text());
  page.on("response", onResponse);
  page.on("console", onConsole);
  const switched = performance.now();
  await page.selectOption("#env", envs[1]);
  await page.waitForFunction(() => !document.getElementById("preview-progress").hidden, null, { timeout: 10_000 });
  assert.match(await page.textContent("#preview-progress"), new RegExp(`preparing ${envs[1]} · ${object}`));
  // A first image of the point in the new scene, rendered directly, before the scene's basis.
  await page.waitForFunction((e) => window.matlas.refined?.env === e || window.matlas.shown?.env === e, envs[1], { timeout: 30_000 });
  const firstImage = performance.now() - switched;
  const refinedFirst = await page.evaluate((e) => window.matlas.refined?.env === e && window.matlas.shown?.env !== e, envs[1]);
  await page.locator(".preview-card").screenshot({ path: join(results, "scene-preparing.png") });
  await settledIn(envs[1], object);
  const ready = performance.now() - switched;
  page.off("response", onResponse);
  page.off("console", onConsole);
  console.log(`scene switch: first image after ${firstImage.toFixed(0)} ms (${refinedFirst ? "refined, before the basis" : "the basis"}), basis after ${ready.toFixed(0)} ms, ${polls.length} status polls`);
  assert.ok(!statuses.includes(503), `no 503 answered: ${statuses}`);
  assert.ok(polls.length >= 1 && polls.every((s) => s === 200), `status polled: ${polls}`);
  assert.deepEqual(consoleErrors, [], "no console errors from the wait");
  assert.equal(statuses[statuses.length - 1], 200);
  assert.ok(await page.locator("#preview-progress").isHidden(), "progress hidden once the image is there");
  assert.equal(await page.evaluate(() => window.matlas.preparing), null);
  assert.equal(await page.getAttribute("#status", "class"), "status", "no error shown");
  await previewIsServers();
  await page.locator(".preview-card").screenshot({ path: join(results, "scene-ready.png") });
});

test("a preview error disappears once a later preview succeeds", async () => {
  // Only the preview's own request fails: the path tool's strip (96 px, still open from an earlier
  // test) redraws on a scene change and may still be asking when this test starts.
  let injected = false;
  const failOnce = (route) => {
    if (injected || route.request().postDataJSON()?.size === 96) return route.fallback();
    injected = true;
    return route.fulfill({
      status: 500, contentType: "application/json", body: JSON.stringify({ error: "injected failure" }),
    });
  };
  await page.route("**/api/preview", failOnce);
  await page.locator("#map").focus();
  await page.keyboard.press("ArrowRight");
  await page.waitForFunction(() => document.getElementById("status").classList.contains("error"), null, { timeout: 10_000 });
  assert.match(await page.textContent("#status"), /preview: injected failure/);
  await page.unroute("**/api/preview", failOnce);
  await page.locator(".preview-card").screenshot({ path: join(results, "error-shown.png") });
  await page.keyboard.press("ArrowLeft");
  await settled();
  await page.waitForFunction(() => !document.getElementById("status").classList.contains("error"), null, { timeout: 10_000 });
  assert.equal((await page.textContent("#status")).trim(), "", "the stale error is gone");
  await previewIsServers();
  await page.locator(".preview-card").screenshot({ path: join(results, "error-cleared.png") });
});

test("switching environment and object together renders that one combination", async () => {
  const { envs, objects, default_object: obj0 } = await page.evaluate(() => window.matlas.model.scenes);
  const env = envs[2], object = objects.find((o) => o !== obj0);
  const requests = recordPreviewRequests();
  const shownBefore = await page.evaluate(() => window.matlas.shownScenes.length);
  await page.selectOption("#env", env);
  await page.selectOption("#object", object);
  await settledIn(env, object);
  requests.stop();
  assert.ok(requests.seen.length > 0 && requests.seen.every((s) => s === `${env}/${object}`),
    `only ${env}/${object} was asked for: ${requests.seen}`);
  const shown = await page.evaluate((n) => window.matlas.shownScenes.slice(n), shownBefore);
  assert.deepEqual(shown, [`${env}/${object}`]);
  await previewIsServers();
  await page.locator(".preview-card").screenshot({ path: join(results, "scene-together.png") });
});

test("a newer scene supersedes one still being prepared", async () => {
  const { envs, objects } = await page.evaluate(() => window.matlas.model.scenes);
  const first = envs[envs.length - 1], object = await page.evaluate(() => window.matlas.object);
  const second = objects.find((o) => o !== object);
  const shownBefore = await page.evaluate(() => window.matlas.shownScenes.length);
  // The page must still be waiting for first/object when the object changes: its status polls are
  // answered "not ready" here however fast the server prepares it (a fast machine had it ready, and
  // rightly shown, between the two selections).
  const held = (u) => u.pathname.endsWith("/api/preview/status") && u.searchParams.get("env") === first &&
    u.searchParams.get("object") === object;
  const notReady = (route) => route.fulfill({ status: 200, contentType: "application/json",
    body: JSON.stringify({ env: first, object, ready: false, progress: 0, stage: "rendering the basis", seconds: 0 }) });
  await page.route(held, notReady);
  await page.selectOption("#env", first);
  await page.waitForFunction((e) => window.matlas.preparing?.env === e, first, { timeout: 10_000 });
  await page.selectOption("#object", second);
  await page.unroute(held, notReady);
  await settledIn(first, second);
  // Long enough for the superseded scene to be ready on the server: its image must not show up.
  await page.waitForTimeout(1500);
  const shown = await page.evaluate((n) => window.matlas.shownScenes.slice(n), shownBefore);
  assert.deepEqual(shown, [`${first}/${second}`], "the superseded scene was never shown");
  await previewIsServers();
  await page.locator(".preview-card").screenshot({ path: join(results, "scene-superseded.png") });
});

test("while the scene's thumbnails are being prepared, the tooltip shows the default scene's", async () => {
  const { env, defaultEnv } = await page.evaluate(() => ({ env: window.matlas.env, defaultEnv: window.matlas.model.scenes.default_env }));
  assert.notEqual(env, defaultEnv, "the tests above left a scene other than the default");
  const busy = (route) => route.fulfill({ status: 503, contentType: "application/json", body: JSON.stringify({ error: "being prepared" }) });
  const pattern = (u) => u.pathname.startsWith("/api/thumbnail/") && u.searchParams.get("env") === env;
  await page.route(pattern, busy);
  const [mx, my] = await page.evaluate(() => window.matlas.map.materialClientPosition(4));
  await page.mouse.move(mx, my);
  await page.waitForFunction((e) => {
    const img = document.querySelector("#tooltip img");
    return !document.getElementById("tooltip").hidden && img.complete && img.naturalWidth > 0 &&
      new URL(img.src).searchParams.get("env") === e;
  }, defaultEnv, { timeout: 10_000 });
  await page.locator(".map-wrap").screenshot({ path: join(results, "tooltip-fallback.png") });
  await page.unroute(pattern, busy);
  await page.mouse.move(mx + 200, my + 200);
});
