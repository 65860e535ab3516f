// Browser tests of the material designer's tools (issue 26, docs/WEB.md): Debian's Chromium
// (headless) driven by playwright-core against `matlas demo` (16x16x32 grid, q = 2; one test
// starts a q = 3 demo).
//
//   MATLAS_BIN=../build/matlas node --test tests/designer.test.mjs
//
// Checks: the layout at 1280x800 and 1920x1080 (no horizontal overflow, single-line titles,
// toolbar and top bar, the real-time card beside the reference render, the four panels in one row,
// no empty bar for the scene view when it is off; screenshots layout-1280.png, layout-1920.png);
// the help dialog (shortcuts, "variance", "plausible", links to the docs served as pages) and the first-run map hint (gone once the
// map is used, also after a reload); the top bar's scene drives the real-time view unless it has its
// own; the real-time card's errors (no WebGL2, coefficients failing) and progress show in the card;
// the slice's colour scale is the server's maximum, the lobe's rings, the path's captions; search
// goes to a material and the name goes once the point moves; the database grid goes to a material;
// the short list compares materials in the same scene (the server's images) and exports their
// tables; the address bar restores a view; a sample file lands on its material with an
// uncertainty ellipse and a fit panel, a plan downloads, a bad file shows its error (screenshot
// web-fit-samples.png); at q = 3 points fade away from the displayed slice.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { mkdtempSync, mkdirSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { chromium } from "playwright-core";

import { openPage, startDemo, webDir as here, stopServer } from "./server.mjs";

/** Software WebGL2 in headless Chromium (as tests/realtime.test.mjs). */
const webglArgs = ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
  "--ignore-gpu-blocklist", "--disable-quic", "--no-first-run", "--disable-background-networking",
  "--disable-component-update", "--disable-sync"];

const work = mkdtempSync(join(tmpdir(), "matlas-designer-"));
const results = join(here, "test-results");
mkdirSync(results, { recursive: true });
let server, url, context, page;

async function api(path, body) {
  const res = await fetch(new URL(path, url), body === undefined ? {} : {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  });
  assert.equal(res.status, 200, `${path}: ${res.status}`);
  return { bytes: Buffer.from(await res.arrayBuffer()), headers: res.headers };
}

/** Bytes of the image shown by an <img> (a blob: URL) in the page. */
async function imageBytes(locator) {
  const b64 = await locator.evaluate(async (img) => {
    const buf = new Uint8Array(await (await fetch(img.src)).arrayBuffer());
    let s = "";
    for (const v of buf) s += String.fromCharCode(v);
    return btoa(s);
  });
  return Buffer.from(b64, "base64");
}

const sameX = (a, b) => a.length === b.length && a.every((v, d) => Math.abs(v - b[d]) < 1e-12);

before(async () => {
  ({ url, server } = await startDemo(work));
  // No WebGL here (the real-time view has its own contexts below): the view's error shows instead.
  ({ context, page } = await openPage(work, url, { acceptDownloads: true, args: ["--disable-3d-apis"],
    onPage: (p) => p.setDefaultNavigationTimeout(120_000) }));
});

after(async () => {
  await context?.close();
  await stopServer(server);
  rmSync(work, { recursive: true, force: true });
});

/** Layout facts of the page at its current size. */
function layoutFacts() {
  return page.evaluate(() => {
    const box = (el) => el.getBoundingClientRect();
    const card = (label) => box(document.querySelector(`.card[aria-label="${label}"]`));
    const doc = document.documentElement;
    const titles = [...document.querySelectorAll(".card h2")].map((h) => ({
      text: h.textContent.trim().slice(0, 30), height: box(h).height, overflow: h.scrollWidth - h.clientWidth,
    }));
    const toolbar = document.querySelector(".map-card .toolbar"), topbar = document.querySelector(".topbar");
    const cards = [...document.querySelectorAll(".card")].map((c) => ({ label: c.getAttribute("aria-label"), ...box(c).toJSON() }));
    return {
      viewport: [innerWidth, innerHeight], scrollWidth: doc.scrollWidth, clientWidth: doc.clientWidth, titles,
      toolbar: { height: box(toolbar).height, overflow: toolbar.scrollWidth - toolbar.clientWidth },
      topbar: { height: box(topbar).height, overflow: topbar.scrollWidth - topbar.clientWidth },
      map: card("latent map"), preview: card("reference render"), realtime: card("real-time view"),
      panels: ["largest weights", "slice", "lobe", "albedo"].map(card), cards,
      giWrap: box(document.querySelector(".gi-wrap")).height,
      slicePlot: box(document.getElementById("slice-plot")).toJSON(),
      // Visible controls sticking out of their card (the right or left edge, 1 px slack).
      outside: [...document.querySelectorAll(".card")].flatMap((c) => {
        const b = box(c);
        return [...c.querySelectorAll("select, button, input:not(.visually-hidden), label, output, .row > span")]
          .filter((e) => e.offsetParent !== null && box(e).width > 0)
          .filter((e) => box(e).right > b.right + 1 || box(e).left < b.left - 1)
          .map((e) => `${c.getAttribute("aria-label")}: ${e.id || e.tagName.toLowerCase()} "${e.textContent.trim().slice(0, 20)}" ${Math.round(box(e).left)}-${Math.round(box(e).right)} outside ${Math.round(b.left)}-${Math.round(b.right)}`);
      }),
      // Rows of controls that wrap onto a second line (their items' tops differ by a line or more).
      // (a group of buttons, .row.buttons, may take two lines)
      wrapped: [...document.querySelectorAll(".card .row:not(.buttons)")]
        .filter((r) => r.offsetParent !== null)
        .filter((r) => {
          const tops = [...r.children].filter((e) => e.offsetParent !== null && box(e).height > 2).map((e) => box(e).top);
          return tops.length > 1 && Math.max(...tops) - Math.min(...tops) > 14;
        })
        .map((r) => `${r.closest(".card").getAttribute("aria-label")}: ${r.textContent.replace(/\s+/g, " ").trim().slice(0, 40)}`),
    };
  });
}

for (const [width, height] of [[1280, 800], [1920, 1080]]) {
  test(`the layout fits ${width}x${height}: no overflow, single-line titles and toolbars, no empty area`, async () => {
    await page.setViewportSize({ width, height });
    await page.waitForTimeout(300);
    const f = await layoutFacts();
    assert.ok(f.scrollWidth <= f.clientWidth, `no horizontal scrolling: ${f.scrollWidth} > ${f.clientWidth}`);
    for (const t of f.titles) {
      assert.ok(t.height <= 20, `title "${t.text}" on one line: ${t.height} px`);
      assert.ok(t.overflow <= 0, `title "${t.text}" not cut: ${t.overflow} px`);
    }
    assert.ok(f.toolbar.height <= 34 && f.toolbar.overflow <= 0, `map toolbar on one line: ${JSON.stringify(f.toolbar)}`);
    assert.ok(f.topbar.height <= 56 && f.topbar.overflow <= 0, `top bar on one line: ${JSON.stringify(f.topbar)}`);
    // The first row: map, reference render and real-time view side by side, same height.
    for (const c of [f.preview, f.realtime]) {
      assert.equal(Math.round(c.top), Math.round(f.map.top), "the top row's cards start together");
      assert.equal(Math.round(c.height), Math.round(f.map.height), "and end together (no empty area under one)");
    }
    assert.ok(f.map.right <= f.preview.left && f.preview.right <= f.realtime.left, "map | reference | real-time");
    // The four panels in one row under it, each as high as the others.
    for (const p of f.panels) {
      assert.equal(Math.round(p.top), Math.round(f.panels[0].top), "panels in one row");
      assert.equal(Math.round(p.height), Math.round(f.panels[0].height));
      assert.ok(p.top >= f.map.bottom, "under the top row");
    }
    // Every card inside the page's width; no two cards overlap.
    for (const c of f.cards) assert.ok(c.left >= 0 && c.right <= width, `${c.label} inside the width`);
    for (let i = 0; i < f.cards.length; i++)
      for (let j = i + 1; j < f.cards.length; j++) {
        const a = f.cards[i], b = f.cards[j];
        assert.ok(!(a.left < b.right - 1 && b.left < a.right - 1 && a.top < b.bottom - 1 && b.top < a.bottom - 1),
          `${a.label} and ${b.label} overlap`);
      }
    assert.deepEqual(f.outside, [], "every control inside its card");
    assert.deepEqual(f.wrapped, [], "rows of controls on one line");
    assert.equal(f.giWrap, 0, "the scene view switched off shows no empty bar");
    assert.ok(f.slicePlot.height <= 260, `the slice panel is not a large square: ${JSON.stringify(f.slicePlot)}`);
    // Nothing much past the viewport for the top row: the map, previews and controls are all seen.
    assert.ok(f.map.bottom <= height + 40, `the top row fits the window's height: ends at ${f.map.bottom}`);
    await page.screenshot({ path: join(results, `layout-${width}.png`) });
  });
}

test("the help dialog explains the panels, the words and the shortcuts; controls have tooltips", async () => {
  await page.setViewportSize({ width: 1440, height: 1000 });
  await page.locator("body").click({ position: { x: 5, y: 5 } });
  await page.keyboard.press("?");
  const help = page.locator("#help");
  await help.waitFor({ state: "visible", timeout: 5_000 });
  const text = await help.textContent();
  for (const word of ["Variance", "Plausible", "Shift", "Alt", "θh × θd slice", "Lobe", "Real-time"])
    assert.ok(text.includes(word), `the help mentions ${word}`);
  // The docs of the served version, as pages: every link of the help's docs paragraph answers.
  const docs = await page.locator("#help-docs a[href^='docs/']").evaluateAll((as) => as.map((a) => a.href));
  assert.ok(docs.some((h) => h.endsWith("docs/WEB.html")), `the help links the browser's docs: ${docs}`);
  for (const href of docs) {
    const res = await fetch(href);
    assert.equal(res.status, 200, href);
    assert.match(await res.text(), /<h1 id="[^"]+">/, `${href} is a rendered doc`);
  }
  await page.screenshot({ path: join(results, "help.png") });
  await page.keyboard.press("Escape");
  await help.waitFor({ state: "hidden", timeout: 5_000 });
  await page.click("#help-button");
  await help.waitFor({ state: "visible", timeout: 5_000 });
  await page.click("#help-close");
  await help.waitFor({ state: "hidden", timeout: 5_000 });
  const titled = await page.evaluate(() => document.querySelectorAll("[title]").length);
  assert.ok(titled >= 30, `elements with a tooltip: ${titled}`);
});

test("the first-run hint shows until the map is used, and stays gone after a reload", async () => {
  await page.evaluate(() => localStorage.clear());
  await page.reload();
  await page.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 30_000 });
  const hint = page.locator("#map-hint");
  assert.ok(await hint.isVisible(), "hint shown on a first visit");
  assert.match(await hint.textContent(), /Click or drag the map/);
  const box = await page.locator("#map").boundingBox();
  await page.mouse.click(box.x + box.width * 0.6, box.y + box.height * 0.7);
  assert.ok(await hint.isHidden(), "hint gone once the map is used");
  await page.reload();
  await page.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 30_000 });
  assert.ok(await page.locator("#map-hint").isHidden(), "and after a reload");
});

test("without WebGL2 the real-time card says so in the card, not 'loading' forever", async () => {
  const err = page.locator("#rt-error");
  await err.waitFor({ state: "visible", timeout: 10_000 });
  assert.match(await err.textContent(), /WebGL2/);
  assert.ok(await page.locator("#rt-progress").isHidden(), "no progress bar left");
  assert.doesNotMatch(await page.textContent("#rt-info"), /loading/);
  assert.doesNotMatch(await page.textContent("#status"), /real-time/, "the error is not in another card");
  assert.ok(await page.locator("#rt-exposure").isDisabled() && await page.locator("#rt-reset").isDisabled(), "its controls are disabled");
  await page.locator(".realtime-card").screenshot({ path: join(results, "realtime-no-webgl.png") });
});

test("the slice has degree ticks and a colour scale up to the server's maximum; the lobe has rings; the path strip captions", async () => {
  await page.waitForFunction(() => window.matlasPanels?.slice.drawn && window.matlas.lastWeights &&
    JSON.stringify(window.matlas.lastWeights.x) === JSON.stringify(window.matlas.x), null, { timeout: 20_000 });
  const { x, drawn, rings } = await page.evaluate(() => ({
    x: window.matlas.x, drawn: window.matlasPanels.slice.drawn, rings: window.matlasPanels.lobe.rings,
  }));
  const phi = Number(await page.inputValue("#phi"));
  const { headers } = await api("api/slice", { x, phi_d: phi });
  const max = Number(headers.get("x-matlas-max"));
  assert.ok(Math.abs(drawn.max - max) <= 1e-6 * max, `colour scale top ${drawn.max} = server's ${max}`);
  assert.equal(drawn.valueTicks[0], 0);
  assert.ok(drawn.valueTicks.length >= 2 && drawn.valueTicks.every((v) => v <= max * 1.0001), `ticks ${drawn.valueTicks}`);
  assert.deepEqual(drawn.thetaH.at(-1), 90);
  assert.deepEqual(drawn.thetaD.at(-1), 90);
  assert.match(await page.textContent("#slice-note"), /unmeasured/);
  assert.ok(rings.length >= 1, "the lobe has a radius scale");
  assert.match(await page.textContent("#lobe-legend"), /incident direction/);
  await page.locator(".slice-panel").screenshot({ path: join(results, "slice-scale.png") });

  const names = await page.evaluate(() => window.matlas.model.names);
  await page.selectOption("#path-a", "0");
  await page.selectOption("#path-b", "2");
  await page.click("#path-go");
  const captions = await page.$$eval("#strip .caption", (c) => c.map((e) => e.textContent));
  assert.equal(captions.length, 8);
  assert.equal(captions[0], `t = 0.00 ${names[0]}`);
  assert.equal(captions[7], `t = 1.00 ${names[2]}`);
  assert.equal(captions[3], "t = 0.43");
  await page.click("#path-clear");
});

test("search goes to a material, and its name goes once the point moves away", async () => {
  const model = await page.evaluate(() => window.matlas.model);
  // Part of material 4's name: Enter goes to the first material whose name contains it.
  const typed = model.names[4].slice(0, Math.max(3, model.names[4].length - 2));
  const i = model.names.findIndex((n) => n.toLowerCase().includes(typed.toLowerCase())), name = model.names[i];
  await page.keyboard.press("/");
  assert.equal(await page.evaluate(() => document.activeElement.id), "search", "/ focuses the search");
  await page.keyboard.type(typed);
  const shown = await page.$$eval("#library .tile", (t) => t.filter((e) => !e.hidden).length);
  assert.ok(shown >= 1 && shown < model.count, `the grid is filtered: ${shown} of ${model.count}`);
  await page.keyboard.press("Enter");
  await page.waitForFunction((i) => JSON.stringify(window.matlas.x) === JSON.stringify(window.matlas.model.latent[i]), i, { timeout: 5_000 });
  assert.equal(await page.inputValue("#search"), name);
  assert.equal(await page.textContent("#at-material"), name);
  assert.ok(await page.locator(`#library .tile[data-index="${i}"]`).evaluate((t) => t.classList.contains("current")));
  // Move away: the name must not stay.
  await page.locator("#map").focus();
  await page.keyboard.press("ArrowRight");
  await page.waitForFunction((i) => JSON.stringify(window.matlas.x) !== JSON.stringify(window.matlas.model.latent[i]), i);
  assert.equal(await page.inputValue("#search"), "", "the search no longer names the material");
  assert.notEqual(await page.textContent("#at-material"), name);
  // A name that matches nothing says so.
  await page.fill("#search", "no-such-material-zzz");
  await page.press("#search", "Enter");
  assert.match(await page.textContent("#status"), /no material named like/);
  await page.fill("#search", "");
  await page.press("#search", "Escape");
});

test("the database grid shows every material and goes to the one clicked", async () => {
  const model = await page.evaluate(() => window.matlas.model);
  assert.equal(await page.locator("#library .tile").count(), model.count);
  const tile = page.locator('#library .tile[data-index="6"] img');
  await tile.scrollIntoViewIfNeeded();
  await page.waitForFunction(() => {
    const img = document.querySelector('#library .tile[data-index="6"] img');
    return img.complete && img.naturalWidth > 0;
  }, null, { timeout: 20_000 });
  const src = new URL(await tile.getAttribute("src"), url);
  assert.equal(src.pathname, "/api/thumbnail/6");
  await tile.click();
  await page.waitForFunction(() => JSON.stringify(window.matlas.x) === JSON.stringify(window.matlas.model.latent[6]), null, { timeout: 5_000 });
});

test("the short list compares materials in one scene with the server's images and exports them together", async () => {
  const model = await page.evaluate(() => window.matlas.model);
  for (const i of [1, 2]) await page.click(`#library .tile[data-index="${i}"] .tile-btn`);
  // The current point too (material 6 from the test above).
  await page.click("#list-add");
  const list = await page.evaluate(() => window.matlas.shortlist);
  assert.deepEqual(list.map((it) => it.index), [1, 2, 6]);
  await page.waitForFunction(() => document.getElementById("compare").dataset.ready === "3", null, { timeout: 30_000 });
  const { env, object } = await page.evaluate(() => ({ env: window.matlas.env, object: window.matlas.object }));
  const tiles = page.locator("#compare .tile img");
  assert.equal(await tiles.count(), 3);
  for (const [k, i] of [1, 2, 6].entries()) {
    const expected = await api("api/preview", { x: model.latent[i], env, object, size: model.preview.size });
    assert.deepEqual(await imageBytes(tiles.nth(k)), expected.bytes, `comparison ${k} is the server's image of ${model.names[i]} in ${env}/${object}`);
  }
  assert.deepEqual(await page.$$eval("#compare .caption", (c) => c.map((e) => e.textContent)), [1, 2, 6].map((i) => model.names[i]));
  await page.locator(".compare-card").screenshot({ path: join(results, "compare.png") });

  // Export: list.json and one MERL table per listed material, each the server's.
  const downloads = [];
  const onDownload = (d) => downloads.push(d);
  page.on("download", onDownload);
  await page.click("#list-export");
  await page.waitForFunction(() => /exported 3 tables/.test(document.getElementById("status").textContent), null, { timeout: 30_000 });
  for (let t = 0; downloads.length < 4 && t < 50; t++) await page.waitForTimeout(100);
  page.off("download", onDownload);
  assert.deepEqual(downloads.map((d) => d.suggestedFilename()),
    ["matlas-list.json", ...[1, 2, 6].map((i, k) => `0${k + 1}-${model.names[i].replace(/[^\w.-]+/g, "_")}.binary`)]);
  const json = JSON.parse(readFileSync(await saved(downloads[0], "list.json"), "utf8"));
  assert.deepEqual(json.materials.map((m) => m.name), [1, 2, 6].map((i) => model.names[i]));
  const table = readFileSync(await saved(downloads[2], "second.binary"));
  assert.deepEqual(table, (await api("api/export", { x: model.latent[2], material: 2 })).bytes, "the second table is material 2's own");

  // The same list as MaterialX: the fits first (their errors in list.json), then one file each.
  const fitted = [];
  const onFit = (d) => fitted.push(d);
  page.on("download", onFit);
  await page.selectOption("#list-format", "mtlx");
  await page.click("#list-export");
  await page.waitForFunction(() => /exported 3 fits/.test(document.getElementById("status").textContent), null, { timeout: 120_000 });
  for (let t = 0; fitted.length < 4 && t < 50; t++) await page.waitForTimeout(100);
  page.off("download", onFit);
  assert.match(await page.textContent("#status"), /largest relative RMS \d+\.\d %, albedo within \d+\.\d %/);
  assert.deepEqual(fitted.map((d) => d.suggestedFilename()),
    ["matlas-list.json", ...[1, 2, 6].map((i, k) => `0${k + 1}-${model.names[i].replace(/[^\w.-]+/g, "_")}.mtlx`)]);
  const listed = JSON.parse(readFileSync(await saved(fitted[0], "fits.json"), "utf8"));
  assert.equal(listed.format, "mtlx");
  const report = JSON.parse((await api("api/fit", { x: model.latent[6], material: 6 })).bytes.toString());
  assert.deepEqual(listed.materials[2].fit_error, { relative_rms: report.error.relative_rms, albedo_error: report.error.albedo_error });
  assert.deepEqual(readFileSync(await saved(fitted[3], "third.mtlx")),
    (await api("api/fit/file", { x: model.latent[6], material: 6, format: "mtlx" })).bytes, "the third file is material 6's fit");

  // As Blender 2.8-3.6 scripts: the Principled v1 fits, their errors in list.json.
  const scripts = [];
  const onScript = (d) => scripts.push(d);
  page.on("download", onScript);
  await page.selectOption("#list-format", "py-v1");
  await page.click("#list-export");
  await page.waitForFunction(() => /exported 3 fits \(Blender 2\.8-3\.6/.test(document.getElementById("status").textContent), null,
    { timeout: 120_000 });
  for (let t = 0; scripts.length < 4 && t < 50; t++) await page.waitForTimeout(100);
  page.off("download", onScript);
  assert.deepEqual(scripts.map((d) => d.suggestedFilename()),
    ["matlas-list.json", ...[1, 2, 6].map((i, k) => `0${k + 1}-${model.names[i].replace(/[^\w.-]+/g, "_")}.py`)]);
  const listedV1 = JSON.parse(readFileSync(await saved(scripts[0], "fits-v1.json"), "utf8"));
  const reportV1 = JSON.parse((await api("api/fit", { x: model.latent[6], material: 6, model: "principled-v1" })).bytes.toString());
  assert.deepEqual(listedV1.materials[2].fit_error, { relative_rms: reportV1.error.relative_rms, albedo_error: reportV1.error.albedo_error });
  assert.deepEqual(readFileSync(await saved(scripts[3], "third-v1.py")),
    (await api("api/fit/file", { x: model.latent[6], material: 6, format: "py", model: "principled-v1" })).bytes,
    "the third file is material 6's Blender 2.8-3.6 fit");
  await page.selectOption("#list-format", "binary");

  // Removing one from the comparison.
  await page.click("#compare .tile:nth-child(1) .tile-btn");
  assert.deepEqual(await page.evaluate(() => window.matlas.shortlist.map((it) => it.index)), [2, 6]);
});

async function saved(download, name) {
  const path = join(work, name);
  await download.saveAs(path);
  return path;
}

test("the address bar keeps the view and restores it in a new page", async () => {
  const model = await page.evaluate(() => window.matlas.model);
  // Zoom in and move the point off any material.
  const box = await page.locator("#map").boundingBox();
  await page.mouse.move(box.x + box.width * 0.4, box.y + box.height * 0.45);
  await page.mouse.wheel(0, -400);
  await page.mouse.click(box.x + box.width * 0.42, box.y + box.height * 0.47);
  await page.selectOption("#layer", "variance");
  await page.waitForTimeout(800);
  const before = await page.evaluate(() => ({
    x: window.matlas.x, env: window.matlas.env, view: window.matlas.map.viewState(),
    list: window.matlas.shortlist.map((it) => it.index), hash: location.hash,
  }));
  assert.match(before.hash, /x=.*env=.*layer=variance.*view=.*list=2;6/);
  const other = await context.newPage();
  try {
    await other.goto(new URL(before.hash, url).href);
    await other.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 30_000 });
    const after = await other.evaluate(() => ({
      x: window.matlas.x, env: window.matlas.env, view: window.matlas.map.viewState(),
      list: window.matlas.shortlist.map((it) => it.index), layer: document.getElementById("layer").value,
    }));
    assert.ok(sameX(after.x, before.x.map((v) => Number(v.toPrecision(7)))), `point ${after.x} vs ${before.x}`);
    assert.equal(after.env, before.env);
    assert.deepEqual(after.list, before.list);
    assert.equal(after.layer, "variance");
    for (const k of ["cx", "cy", "half"]) assert.ok(Math.abs(after.view[k] - before.view[k]) <= 1e-6 * (1 + Math.abs(before.view[k])), `view ${k}`);
    assert.equal(model.count, await other.evaluate(() => window.matlas.model.count));
  } finally {
    await other.close();
  }
  await page.selectOption("#layer", "albedo");
});

// --- the real-time view with (software) WebGL2 -------------------------------------------------

async function webglPage(name, onPage = () => {}) {
  const ctx = await chromium.launchPersistentContext(join(work, name), {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true,
    viewport: { width: 1280, height: 800 }, args: webglArgs,
  });
  try {
    const p = ctx.pages()[0] ?? (await ctx.newPage());
    p.on("pageerror", (e) => console.error("page error:", e));
    p.setDefaultNavigationTimeout(120_000);  // software WebGL on a loaded 2-core machine
    await onPage(p);
    await p.goto(url);
    return { ctx, p };
  } catch (e) {
    await ctx.close();  // a browser left open would keep this test file from exiting
    throw e;
  }
}

test("the top bar's environment and object drive the real-time view unless it has its own scene", async () => {
  const { ctx, p } = await webglPage("profile-rt");
  try {
    await p.waitForFunction(() => window.matlasViewer?.env, null, { timeout: 120_000 });
    const { envs, objects } = await p.evaluate(() => window.matlas.model.scenes);
    const env = envs[1], object = objects.find((o) => o !== "sphere");
    // A new environment's real-time maps wait for the preview's first image of it (or 3 s), so
    // the server does not prefilter them while it renders that image.
    const asked = p.waitForRequest((r) => r.url().includes(`api/realtime/environment/${env}`), { timeout: 60_000 });
    const switched = Date.now();
    await p.selectOption("#env", env);
    await asked;
    const waited = Date.now() - switched;
    const imageEnvs = await p.evaluate(() => [window.matlas.shown?.env, window.matlas.refined?.env]);
    assert.ok(imageEnvs.includes(env) || waited >= 2900,
      `the maps were asked for after ${waited} ms with the preview on ${JSON.stringify(imageEnvs)}`);
    await p.selectOption("#object", object);
    await p.waitForFunction(([e, o]) => window.matlasViewer.env === e && window.matlasViewer.object === o, [env, object], { timeout: 60_000 });
    assert.equal(await p.inputValue("#rt-env"), env);
    assert.ok(await p.locator("#rt-env").isDisabled(), "the card's own pickers are off while it follows the top bar");
    // Its own scene: the card's pickers apply, the top bar no longer moves it.
    await p.check("#rt-own");
    await p.selectOption("#rt-env", envs[2]);
    await p.waitForFunction((e) => window.matlasViewer.env === e, envs[2], { timeout: 60_000 });
    await p.selectOption("#env", envs[0]);
    await p.waitForFunction((e) => window.matlas.env === e, envs[0], { timeout: 10_000 });
    await p.waitForTimeout(500);
    assert.equal(await p.evaluate(() => window.matlasViewer.env), envs[2], "own scene kept");
    // Back to the top bar's.
    await p.uncheck("#rt-own");
    await p.waitForFunction((e) => window.matlasViewer.env === e && window.matlasViewer.object === window.matlas.object, envs[0], { timeout: 60_000 });
    assert.ok(await p.locator("#rt-error").isHidden());
  } finally {
    await ctx.close();
  }
});

test("the real-time card shows progress while the coefficients load and an error when they fail", async () => {
  let release;
  const held = new Promise((r) => (release = r));
  const { ctx, p } = await webglPage("profile-rt-fail", async (p) => {
    await p.route("**/api/realtime", async (route) => {
      await held;
      await route.continue();
    });
    await p.route("**/api/realtime/coefficients", (route) => route.fulfill({
      status: 500, contentType: "application/json", body: JSON.stringify({ error: "injected coefficient failure" }),
    }));
  });
  try {
    const progress = p.locator("#rt-progress");
    await progress.waitFor({ state: "visible", timeout: 30_000 });
    // First the card waits for the map's layer, then for the server.
    await p.waitForFunction(() => /computes the real-time coefficients/.test(document.getElementById("rt-progress").textContent),
      null, { timeout: 30_000 });
    assert.match(await progress.textContent(), /computes the real-time coefficients.*\d+ s/);
    release();
    const err = p.locator("#rt-error");
    await err.waitFor({ state: "visible", timeout: 30_000 });
    assert.match(await err.textContent(), /coefficients failed to load \(injected coefficient failure\)/);
    assert.ok(await progress.isHidden(), "no progress left once failed");
    await p.locator(".realtime-card").screenshot({ path: join(results, "realtime-error.png") });
  } finally {
    release();
    await ctx.close();
  }
});

// --- sparse samples (issue 30) -------------------------------------------------------------------

test("a sample file lands on its material with an uncertainty ellipse and a fit panel; a bad file shows its error", async () => {
  await page.setViewportSize({ width: 1280, height: 800 });
  const pageErrors = [];
  const onError = (e) => pageErrors.push(String(e));
  page.on("pageerror", onError);
  const model = await page.evaluate(() => window.matlas.model);
  const k = 3;
  // Samples of material k through the API: its lobes in the plane of incidence (wi on the -x side,
  // phi_i = 180; theta_o > 0 on the mirror side, phi_o = 0) at a few incident angles.
  const lines = ["# samples of " + model.names[k], "theta_i,phi_i,theta_o,phi_o,r,g,b"];
  for (const ti of [10, 25, 40, 55, 70]) {
    const lobe = JSON.parse((await api("api/lobe", { x: model.latent[k], theta_i: ti, samples: 19 })).bytes);
    lobe.theta_o.forEach((to, j) => {
      // With 5 % noise (deterministic), so that the fit has an uncertainty to show.
      const noise = 1 + 0.05 * Math.sin(12.9898 * (lines.length + 1) + 78.233 * ti);
      if (Math.abs(to) < 80 && lobe.rgb[j].every((v) => v > 0))
        lines.push([ti, 180, Math.abs(to), to >= 0 ? 0 : 180, ...lobe.rgb[j].map((v) => v * noise)].join(","));
    });
  }
  assert.ok(lines.length > 20, `${lines.length - 2} samples`);
  await page.setInputFiles("#samples-upload", { name: "measured.csv", mimeType: "text/csv", buffer: Buffer.from(lines.join("\n") + "\n") });
  await page.waitForFunction(() => window.matlas.fitted !== null && window.matlas.map.fitEllipse !== null, null, { timeout: 30_000 });
  const s = await page.evaluate(() => {
    const m = window.matlas.map, f = window.matlas.fitted.reply;
    const [a, b] = m.axes;
    return { reply: f, x: window.matlas.x, ellipse: m.fitEllipse, at: m.toScreen(f.x[a], f.x[b]) };
  });
  assert.equal(s.reply.best_input.index, k, JSON.stringify(s.reply.best_input));
  const extent = model.bounds.max.map((v, d) => v - model.bounds.min[d]);
  s.reply.x.forEach((v, d) => assert.ok(Math.abs(v - model.latent[k][d]) < 0.05 * extent[d], `x[${d}] = ${v} vs ${model.latent[k][d]}`));
  assert.equal(s.reply.used, lines.length - 2);
  assert.ok(sameX(s.x, s.reply.x), "the current point moved to the fit");
  assert.ok(Math.abs(s.ellipse.cx - s.at[0]) < 0.5 && Math.abs(s.ellipse.cy - s.at[1]) < 0.5, "the ellipse is centred on the fit");
  assert.ok(s.ellipse.rx >= s.ellipse.ry && s.ellipse.ry > 0, `the noise leaves an uncertainty: ${JSON.stringify(s.ellipse)}`);
  const panel = page.locator("#fit-panel");
  assert.ok(await panel.isVisible());
  const text = await panel.textContent();
  for (const word of ["measured.csv", `${s.reply.used} samples used`, "outlier", "residual", model.names[k]])
    assert.ok(text.includes(word), `the fit panel says "${word}": ${text}`);
  await page.waitForFunction(() => window.matlas.shown && window.matlas.shown.x.every((v, d) => v === window.matlas.x[d]), null, { timeout: 30_000 });
  await page.screenshot({ path: join(results, "web-fit-samples.png") });

  // "plan…" downloads the next directions given the samples fitted, as a sample file.
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#sample-plan")]);
  const csv = readFileSync(await download.path(), "utf8").trim().split("\n").filter((l) => !l.startsWith("#"));
  assert.match(csv[0], /^theta_i,phi_i,theta_o,phi_o/);
  assert.equal(csv.length - 1, 10);
  assert.equal(new Set(csv.slice(1)).size, 10, "distinct directions");
  assert.equal((await page.evaluate(() => window.matlas.plan)).conditionedOn, s.reply.used);

  // A file whose only row is below the horizon: the parser's message in the panel and the status line.
  await page.setInputFiles("#samples-upload", { name: "bad.csv", mimeType: "text/csv",
    buffer: Buffer.from("theta_i,phi_i,theta_o,phi_o,r,g,b\n95,0,10,0,0.1,0.1,0.1\n") });
  await page.waitForFunction(() => document.getElementById("fit-panel").classList.contains("failed"), null, { timeout: 10_000 });
  const error = await page.locator("#fit-panel .fit-error").textContent();
  assert.match(error, /line 2/);
  assert.match(error, /horizon/);
  assert.match(await page.locator("#status").textContent(), /line 2/);
  assert.equal(await page.evaluate(() => window.matlas.fitted), null);
  assert.equal(await page.evaluate(() => window.matlas.map.fitted), null, "no marker for a failed fit");
  await page.locator(".map-card").screenshot({ path: join(results, "web-fit-samples-error.png") });
  await page.click("#fit-close");
  assert.ok(!(await panel.isVisible()));
  page.off("pageerror", onError);
  assert.deepEqual(pageErrors, [], "no uncaught error in the page");
  await page.setViewportSize({ width: 1440, height: 1000 });
});

// --- q > 2: distance from the displayed slice ---------------------------------------------------

test("at q = 3 points and labels fade with their distance from the slice; the legend says what a far point is", async () => {
  const work3 = join(work, "q3");
  mkdirSync(work3, { recursive: true });
  const { url: url3, server: server3 } = await startDemo(work3, ["-q", "3"]);
  // Its own browser, assigned before the page loads, so that a failed load still closes it.
  const ctx3 = await chromium.launchPersistentContext(join(work3, "profile"), {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true, viewport: { width: 1280, height: 800 },
    args: ["--no-sandbox", "--disable-gpu", "--disable-3d-apis", "--no-first-run", "--disable-background-networking"],
  });
  try {
    const p3 = ctx3.pages()[0] ?? (await ctx3.newPage());
    p3.on("pageerror", (e) => console.error("page error:", e));
    p3.setDefaultNavigationTimeout(120_000);
    await p3.goto(url3);
    await p3.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 60_000 });
    const model = await p3.evaluate(() => window.matlas.model);
    assert.equal(model.dim, 3);
    // At material 0 (the page's start) its own marker is opaque.
    await p3.waitForFunction(() => window.matlas.map.markerAlpha.length > 0);
    const near = await p3.evaluate(() => ({ alpha: window.matlas.map.markerAlpha, labels: window.matlas.map.labelBoxes.length }));
    assert.equal(near.alpha[0], 1);
    // x3 at its slider's maximum: far from (nearly) every material.
    await p3.$eval('#sliders input[data-dim="2"]', (s) => {
      s.value = s.max;
      s.dispatchEvent(new Event("input", { bubbles: true }));
      s.dispatchEvent(new Event("change", { bubbles: true }));
    });
    await p3.waitForTimeout(300);
    const far = await p3.evaluate(() => ({ alpha: window.matlas.map.markerAlpha, labels: window.matlas.map.labelBoxes.map((l) => l.index), x: window.matlas.x }));
    const mean = (v) => v.reduce((a, b) => a + b, 0) / v.length;
    assert.ok(mean(far.alpha) < 0.5 * mean(near.alpha), `mean opacity ${mean(far.alpha).toFixed(3)} vs ${mean(near.alpha).toFixed(3)}`);
    for (const i of far.labels) assert.ok(far.alpha[i] >= 0.5, `a faded material (${far.alpha[i]}) is not labelled`);
    // The opacity is the stated function of the distance along x3.
    const span = model.bounds.max[2] - model.bounds.min[2];
    for (const i of [0, 1, 2]) {
      const d = (model.latent[i][2] - far.x[2]) / span;
      assert.ok(Math.abs(far.alpha[i] - (0.1 + 0.9 * Math.exp(-((d / 0.15) ** 2)))) < 1e-9, `alpha of ${i}`);
    }
    assert.match(await p3.textContent("#legend-far"), /fade with their distance from the displayed slice/);
    assert.match(await p3.textContent("#legend-layer"), /mix of the nearest materials/, "convex: a far point is not the database mean");
    await p3.locator(".map-card").screenshot({ path: join(results, "map-q3-far.png") });
    const bar = await p3.evaluate(() => { const t = document.querySelector(".map-card .toolbar"); return { sw: t.scrollWidth, cw: t.clientWidth, h: t.getBoundingClientRect().height }; });
    assert.ok(bar.sw <= bar.cw && bar.h <= 34, `the q = 3 toolbar (with the axes) stays on one line at 1280 px: ${JSON.stringify(bar)}`);
  } finally {
    await ctx3.close();
    await stopServer(server3);
  }
});
