// The real-time view of one material as a user sees it: the page of a running `matlas serve` at a
// given size, the point set to the material's latent position and the environment chosen through
// the address (the page's shareable view), the full frame drawn, then the view's canvas and the
// whole page saved as PNGs. For looking at the viewer's shading (docs/REALTIME.md) on a real model.
//
//   node bench/realtime_screenshot.mjs http://127.0.0.1:8080/ MATERIAL ENV OUT [1280x800]
//   -> OUT-canvas.png, OUT-page.png
import { openChromium } from "./chromium.mjs";

const [url = "http://127.0.0.1:8080/", material, env = "studio", out = "/tmp/realtime", size = "1280x800"] =
  process.argv.slice(2);
if (!material) throw new Error("usage: realtime_screenshot.mjs URL MATERIAL ENV OUT [WxH]");
const [width, height] = size.split("x").map(Number);
const model = await (await fetch(new URL("api/model", url))).json();
const i = model.names.indexOf(material);
if (i < 0) throw new Error(`${material} is not in the model (${model.names.length} materials)`);
const { page, close } = await openChromium({ viewport: { width, height }, webgl: true });
try {
  page.on("console", (m) => m.type() === "error" && console.error("page:", m.text()));
  await page.goto(`${url}#x=${model.latent[i].join(",")}&env=${encodeURIComponent(env)}`);
  await page.waitForFunction((name) => {
    const v = window.matlasViewer, m = window.matlas;
    return v && m && v.env === name && v.shownX && JSON.stringify(v.shownX) === JSON.stringify(m.x) &&
      JSON.stringify(v.lightsX) === JSON.stringify(m.x) &&
      v.gl.frameTimes.length > 0;
  }, env, { timeout: 600_000 });
  await page.evaluate(() => window.matlasViewer.gl.draw());
  await page.locator("#rt-canvas").screenshot({ path: `${out}-canvas.png` });
  await page.screenshot({ path: `${out}-page.png` });
  console.log(`${material} under ${env}: ${out}-canvas.png, ${out}-page.png`);
} finally {
  await close();
}
