// How long a map background layer takes to appear in a real browser (Debian's Chromium, headless,
// through playwright-core) on a running `matlas serve`: switches the layer between albedo and
// plausibility `rounds` times and reports, from the change in the page (the select's change event,
// including the page's 120 ms debounce), the time until the first picture of the layer is on the
// map (the coarse one where the page asks for one first) and until the full-resolution layer is,
// per layer.
//
//   node bench/map_layer_browser.mjs http://127.0.0.1:8080/ [rounds=4]
import { openChromium } from "./chromium.mjs";

const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const rounds = Number(process.argv[3] ?? 4);
const { page, close } = await openChromium({ viewport: { width: 1440, height: 1000 } });
try {
  const opened = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.matlas && window.matlas.map.layer !== null, null, { timeout: 120_000 });
  const firstAny = Date.now() - opened;
  await page.waitForSelector("#map-wrap:not(.layer-loading)", { timeout: 120_000 });
  const firstFull = Date.now() - opened;
  const n = await page.evaluate(() => window.matlas.model.count);
  console.log(`n = ${n}: page opened -> first layer on the map ${firstAny} ms, full layer ${firstFull} ms`);
  const first = { albedo: [], plausibility: [] }, full = { albedo: [], plausibility: [] };
  for (let r = 0; r < rounds; r++) {
    const kind = r % 2 ? "albedo" : "plausibility";
    // Times taken in the page: from the change event to the layer's image replaced, and to idle.
    const t = await page.evaluate(async (kind) => {
      const m = window.matlas, wrap = document.getElementById("map-wrap");
      const before = m.map.layer;
      const sel = document.getElementById("layer");
      const t0 = performance.now();
      sel.value = kind;
      sel.dispatchEvent(new Event("change"));
      let shown = null;
      while (true) {
        await new Promise((res) => requestAnimationFrame(res));
        if (shown === null && m.map.layer !== before && m.map.layer !== null) shown = performance.now() - t0;
        if (shown !== null && !wrap.classList.contains("layer-loading")) return [shown, performance.now() - t0];
        if (performance.now() - t0 > 120_000) throw new Error("no layer within 120 s");
      }
    }, kind);
    first[kind].push(t[0]);
    full[kind].push(t[1]);
  }
  const median = (a) => [...a].sort((x, y) => x - y)[Math.floor(a.length / 2)].toFixed(0);
  const list = (a) => a.map((v) => v.toFixed(0)).join(", ");
  for (const kind of ["plausibility", "albedo"]) {
    console.log(`${kind}, ${first[kind].length} changes: first picture median ${median(first[kind])} ms (${list(first[kind])}), ` +
      `full layer median ${median(full[kind])} ms (${list(full[kind])})`);
  }
  console.log(`coarse layers shown: ${(await page.evaluate(() => window.matlas.layerTiming)).coarseShown}`);
} finally {
  await close();
}
