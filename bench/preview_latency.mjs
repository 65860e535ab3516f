// Pointer-to-image latency of the live preview in a real browser (Debian's Chromium, headless,
// through playwright-core): drags across the latent map of a running `matlas serve`/`matlas demo`
// at 60 pointer events per second and reports, for every preview shown, the time from the pointer
// event to the decoded image on screen (percentiles), as the page itself measures it.
//
//   node bench/preview_latency.mjs http://127.0.0.1:8080/ [drags=5]
import { openChromium } from "./chromium.mjs";

const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const drags = Number(process.argv[3] ?? 5);
const { page, close } = await openChromium({ viewport: { width: 1440, height: 1000 } });
try {
  await page.goto(url);
  await page.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 60_000 });
  const info = await page.evaluate(() => ({ n: window.matlas.model.count, preview: window.matlas.model.preview }));
  const box = await page.locator("#map").boundingBox();
  let all = [];
  for (let d = 0; d < drags; d++) {
    await page.evaluate(() => (window.matlas.latencies.length = 0));
    const y0 = 0.3 + 0.1 * d;
    await page.mouse.move(box.x + box.width * 0.15, box.y + box.height * y0);
    await page.mouse.down();
    for (let k = 0; k <= 90; k++) {
      await page.mouse.move(box.x + box.width * (0.15 + 0.008 * k), box.y + box.height * (y0 + 0.002 * k));
      await page.waitForTimeout(16);
    }
    await page.mouse.up();
    await page.waitForTimeout(300);
    all = all.concat(await page.evaluate(() => window.matlas.latencies.slice()));
  }
  all.sort((a, b) => a - b);
  const q = (p) => all[Math.min(all.length - 1, Math.floor(p * all.length))].toFixed(1);
  console.log(`n = ${info.n}, preview ${info.preview.size} px (dragging: ${info.preview.drag_size} px)`);
  console.log(`${all.length} previews over ${drags} drags: pointer-to-image latency median ${q(0.5)} ms, p90 ${q(0.9)} ms, p99 ${q(0.99)} ms, max ${all[all.length - 1].toFixed(1)} ms`);
} finally {
  await close();
}
