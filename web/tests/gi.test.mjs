// Browser test of the scene view (issue 13, docs/WEB.md): Debian's Chromium (headless) driven by
// playwright-core against `matlas demo` with tiny GI scenes traced on demand (64 x 48, 2 spp).
//
//   MATLAS_BIN=../build/matlas node --test tests/gi.test.mjs
//
// Picking a scene gets 503 while the server traces it, then shows an image; dragging on the map
// changes it during the drag; the shown image has exactly the pixels of `matlas gi` run on the
// same model, point and basis file; another scene shows another image. Screenshots:
// test-results/gi-*.png.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";

import { bin, openPage, startDemo, webDir, stopServer } from "./server.mjs";

const work = mkdtempSync(join(tmpdir(), "matlas-gi-"));
const results = join(webDir, "test-results");
mkdirSync(results, { recursive: true });
let server, url, context, page;
const giStatuses = [];

before(async () => {
  ({ url, server } = await startDemo(work, ["--gi-size", "64x48", "--gi-spp", "2", "--gi-refine-width", "128"]));
  // No WebGL: the real-time view (software-rendered here, a frame per pointer move) would
  // compete with the scene view for the page's thread; it has its own test.
  ({ context, page } = await openPage(work, url, {
    args: ["--disable-3d-apis"],
    onPage: (p) => p.on("response", (r) => { if (new URL(r.url()).pathname === "/api/gi") giStatuses.push(r.status()); }),
  }));
});

after(async () => {
  await context?.close();
  await stopServer(server);
  rmSync(work, { recursive: true, force: true });
});

/** Waits until the scene view shows `scene` at the current point. */
async function giSettled(scene) {
  await page.waitForFunction((s) => {
    const m = window.matlas;
    return m.giShown && m.giShown.scene === s && JSON.stringify(m.giShown.x) === JSON.stringify(m.x) && !m.dragging;
  }, scene, { timeout: 120_000 });
}

/** RGBA pixels of PNG bytes (base64) or of the scene view's image, decoded in the page. */
async function pixels(pngBase64) {
  return page.evaluate(async (b64) => {
    const blob = b64 === null
      ? await (await fetch(document.getElementById("gi").src)).blob()
      : new Blob([Uint8Array.from(atob(b64), (c) => c.charCodeAt(0))], { type: "image/png" });
    const bitmap = await createImageBitmap(blob);
    const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
    const ctx = canvas.getContext("2d");
    ctx.drawImage(bitmap, 0, 0);
    return { width: bitmap.width, height: bitmap.height, data: Array.from(ctx.getImageData(0, 0, bitmap.width, bitmap.height).data) };
  }, pngBase64);
}

test("the scene view is off until a scene is picked, then shows the traced scene", async () => {
  assert.equal(await page.locator("#gi-view").isVisible(), true);
  assert.equal(await page.inputValue("#gi-scene"), "");
  assert.equal(giStatuses.length, 0, "nothing asked while off");
  await page.selectOption("#gi-scene", "floor");
  await giSettled("floor");
  assert.equal(giStatuses[0], 503, "the first request finds the scene being traced");
  assert.equal(giStatuses[giStatuses.length - 1], 200);
  const img = await pixels(null);
  assert.deepEqual([img.width, img.height], [64, 48]);
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-floor.png") });
});

test("dragging on the map changes the scene view during the drag", async () => {
  await giSettled("floor");
  const before = await pixels(null);
  const n0 = await page.evaluate(() => window.matlas.giImages);
  const box = await page.locator("#map").boundingBox();
  await page.mouse.move(box.x + box.width * 0.25, box.y + box.height * 0.6);
  await page.mouse.down();
  let during = 0;
  for (let k = 0; k <= 30; k++) {
    await page.mouse.move(box.x + box.width * (0.25 + 0.015 * k), box.y + box.height * (0.6 - 0.01 * k));
    await page.waitForTimeout(20);
    if (k === 20) during = (await page.evaluate(() => window.matlas.giImages)) - n0;
  }
  await page.mouse.up();
  await giSettled("floor");
  assert.ok(during >= 2, `scene images shown during the drag: ${during}`);
  const after = await pixels(null);
  assert.notDeepEqual(after.data, before.data, "the image changed");
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-dragged.png") });
});

test("the scene view shows the pixels of matlas gi at the same point", async () => {
  await giSettled("floor");
  const x = await page.evaluate(() => window.matlas.giShown.x);
  const models = join(work, "cache", "models");
  const model = join(models, readdirSync(models).find((f) => f.endsWith(".matlas")));
  const basisDir = `${model}.gi`;
  const basis = join(basisDir, readdirSync(basisDir).find((f) => f.startsWith("floor-") && f.endsWith(".safetensors")));
  const out = join(work, "gi-cli.png");
  assert.equal(await page.isChecked("#gi-auto"), true, "automatic exposure by default");
  // The drag's image has its fireflies removed (docs/GI.md): --remove-fireflies gives the same pixels.
  execFileSync(bin, ["gi", model, `--at=${x.join(",")}`, "--basis", basis, "--auto-exposure", "--remove-fireflies", "-o", out],
    { stdio: "pipe" });
  const cli = await pixels(readFileSync(out).toString("base64"));
  const shown = await pixels(null);
  assert.deepEqual([shown.width, shown.height], [cli.width, cli.height]);
  let differing = 0;
  for (let i = 0; i < cli.data.length; i++) if (cli.data[i] !== shown.data[i]) differing++;
  assert.equal(differing, 0, `${differing} of ${cli.data.length} values differ from matlas gi's image`);
  const mean = cli.data.reduce((a, v) => a + v, 0) / cli.data.length;
  assert.ok(mean > 5, `the image is not black (mean ${mean.toFixed(1)})`);
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-cli.png") });
});

test("the exposure slider and tone curve change the scene view; auto comes back", async () => {
  await giSettled("floor");
  const autoImage = await pixels(null);
  const autoStops = Number(await page.getAttribute("#gi", "data-exposure"));
  assert.match(await page.textContent("#gi-exposure-value"), /^[+-]\d+\.\d\d$/);
  const requests = [];
  const onRequest = (r) => new URL(r.url()).pathname === "/api/gi" && requests.push(new URL(r.url()).searchParams);
  page.on("request", onRequest);
  const n0 = await page.evaluate(() => window.matlas.giImages);
  await page.locator("#gi-exposure").fill(String(Math.round(autoStops) + 2));
  await page.waitForFunction((n) => window.matlas.giImages > n && document.getElementById("gi").dataset.exposure !== undefined, n0);
  await page.waitForFunction((e) => Number(document.getElementById("gi").dataset.exposure) === e, Math.round(autoStops) + 2);
  assert.equal(await page.isChecked("#gi-auto"), false, "moving the slider turns auto off");
  const brighter = await pixels(null);
  const mean = (img) => img.data.reduce((a, v) => a + v, 0) / img.data.length;
  assert.ok(mean(brighter) > mean(autoImage), `2 stops over auto is brighter: ${mean(autoImage).toFixed(1)} -> ${mean(brighter).toFixed(1)}`);
  await page.selectOption("#gi-tone", "clamp");
  await page.waitForFunction(() => [...document.querySelectorAll("#gi-tone")].length && true);
  await page.waitForTimeout(300);
  await page.check("#gi-auto");
  await page.selectOption("#gi-tone", "aces");
  await giSettled("floor");
  // The clamp image at auto exposure has the same stops: wait for the ACES one itself.
  await page.waitForFunction(() => window.matlas.giShown.tone === "aces" && window.matlas.giShown.exposure === "auto");
  await page.waitForFunction((e) => Number(document.getElementById("gi").dataset.exposure) === e, autoStops);
  page.off("request", onRequest);
  assert.ok(requests.some((q) => q.get("tone") === "clamp"), "the tone curve is sent");
  assert.equal(requests[requests.length - 1].get("exposure"), "auto");
  assert.deepEqual((await pixels(null)).data, autoImage.data, "auto and ACES again: the first image");
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-exposure.png") });
});

test("at rest the scene view is refined pass after pass; moving the point stops it", async () => {
  await giSettled("floor");
  // The refined image: a direct trace of the point at --gi-refine-width (128 x 96), laid over the
  // composed one from 4 spp on, with more samples as the pointer rests.
  await page.waitForFunction(() => window.matlas.giRefined && window.matlas.giRefined.spp >= 4, null, { timeout: 60_000 });
  const first = await page.evaluate(() => window.matlas.giRefined);
  assert.equal(first.scene, "floor");
  assert.deepEqual(first.x, await page.evaluate(() => window.matlas.x));
  assert.equal(await page.isVisible("#gi-refined"), true);
  assert.match(await page.textContent("#gi-refine"), /spp/);
  const size = await page.evaluate(() => [document.getElementById("gi-refined").naturalWidth, document.getElementById("gi-refined").naturalHeight]);
  assert.deepEqual(size, [128, 96]);
  await page.waitForFunction((spp) => window.matlas.giRefined && window.matlas.giRefined.spp > spp, first.spp, { timeout: 60_000 });
  const later = await page.evaluate(() => window.matlas.giRefined);
  assert.ok(later.spp > first.spp, `more samples at rest: ${first.spp} -> ${later.spp}`);
  assert.ok(later.error > 0 && later.error < 10, `an error estimate from two halves of the passes: ${later.error}`);
  assert.match(await page.textContent("#gi-refine"), new RegExp(`${later.spp} spp · ±`));
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-refined.png") });
  // A move hides the refined image at once and asks the server for the composed image again.
  const box = await page.locator("#map").boundingBox();
  await page.mouse.move(box.x + box.width * 0.4, box.y + box.height * 0.4);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.45, box.y + box.height * 0.45, { steps: 4 });
  assert.equal(await page.evaluate(() => window.matlas.giRefined), null, "no refined image during a drag");
  assert.equal(await page.isVisible("#gi-refined"), false);
  await page.mouse.up();
  await giSettled("floor");
});

test("the refined scene view is denoised by default and labelled; its toggle shows the plain mean", async () => {
  await giSettled("floor");
  await page.waitForFunction(() => window.matlas.giRefined && window.matlas.giRefined.denoised, null, { timeout: 60_000 });
  assert.match(await page.textContent("#gi-refine"), /^denoised · (refining|converged) · \d+ spp/);
  assert.equal(await page.isVisible("#gi-denoise"), true);
  assert.equal(await page.getAttribute("#gi-denoise", "aria-pressed"), "true");
  await page.click("#gi-denoise");
  await page.waitForFunction(() => window.matlas.giRefined && !window.matlas.giRefined.denoised, null, { timeout: 60_000 });
  assert.doesNotMatch(await page.textContent("#gi-refine"), /denoised/);
  assert.equal(await page.getAttribute("#gi-denoise", "aria-pressed"), "false");
  assert.equal(await page.getAttribute("#preview-denoise", "aria-pressed"), "false", "one denoise setting for both views");
  await page.click("#gi-denoise");
  await page.waitForFunction(() => window.matlas.giRefined && window.matlas.giRefined.denoised, null, { timeout: 60_000 });
});

test("the view picker shows the scene from another camera", async () => {
  await giSettled("floor");
  const front = await pixels(null);
  const views = await page.$$eval("#gi-camera option", (o) => o.map((e) => e.value));
  assert.deepEqual(views, ["front", "side", "above"]);
  await page.selectOption("#gi-camera", "side");
  await giSettled("floor@side");
  const side = await pixels(null);
  assert.deepEqual([side.width, side.height], [front.width, front.height]);
  let differing = 0;
  for (let i = 0; i < side.data.length; i += 4) if (Math.abs(side.data[i] - front.data[i]) > 16) differing++;
  assert.ok(differing > side.data.length / 4 / 5, `another camera: ${differing} of ${side.data.length / 4} pixels differ`);
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-side.png") });
  await page.selectOption("#gi-camera", "front");
  await giSettled("floor");
});

test("another scene shows another image", async () => {
  const floor = await pixels(null);
  await page.selectOption("#gi-scene", "box");
  await giSettled("box");
  const box = await pixels(null);
  assert.notDeepEqual(box.data, floor.data);
  await page.locator("#gi-view").screenshot({ path: join(results, "gi-box.png") });
});
