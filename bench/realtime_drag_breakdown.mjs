// Where the time of a map drag goes in the real-time view (docs/BENCHMARKS.md, "Real-time
// viewer"): against a running `matlas serve`, in Debian's headless Chromium with software WebGL2
// (SwiftShader), 512 x 512 canvas. First a reduced frame alone (the page idle) with bands 0..L'
// and the 128² -> 512² stretch alone; then scripted drags, the point moved from JavaScript every
// 16 ms (no input events), with the page as it is, without the map's redraw, and without the map's
// redraw and the other panels (preview, charts, slice, scene view): the reduced frames' times and
// the move-to-frame latency of each.
//
//   node bench/realtime_drag_breakdown.mjs http://127.0.0.1:8080/
import { createRequire } from "node:module";
import { resolve } from "node:path";

const require = createRequire(resolve(import.meta.dirname, "..", "web", "package.json"));
const { chromium } = require("playwright-core");
const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true,
  args: ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"],
});
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];
try {
  for (const variant of ["idle", "everything live", "no map redraw", "no map redraw, no other panels"]) {
    const page = await browser.newPage({ viewport: { width: 1440, height: 1400 } });
    await page.goto(url);
    await page.waitForFunction(() => window.matlasViewer && window.matlasViewer.gl.frameTimes.length > 0, null, { timeout: 600_000 });
    await page.waitForTimeout(3000);  // the first full frame's tiles
    const result = await page.evaluate(async (variant) => {
      const { gl } = window.matlasViewer;
      const ctx = gl.renderer.getContext();
      const wait = () => ctx.readPixels(0, 0, 1, 1, ctx.RGBA, ctx.UNSIGNED_BYTE, new Uint8Array(4));
      const med = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];
      if (variant === "idle") {
        gl.adaptive = false;
        const out = {};
        for (const bands of [0, 1, 2, 4]) {
          gl.fastBands = bands;
          out[`reduced frame, bands 0..${bands}`] = med(Array.from({ length: 15 }, () => gl.draw(true)));
        }
        out["stretch alone"] = med(Array.from({ length: 15 }, () => {
          const t = performance.now();
          gl.renderer.render(gl.blitScene, gl.blitCamera);
          wait();
          return performance.now() - t;
        }));
        return out;
      }
      const map = window.matlas.map;
      if (variant.includes("no map redraw")) map.redraw = () => {};
      if (variant.includes("no other panels"))
        for (const sel of [".chart", "#slice", "#preview", "#gi-view", "#strip"])
          for (const e of document.querySelectorAll(sel)) e.style.display = "none";
      const v = window.matlasViewer;
      const frames = gl.fastFrameTimes.length;
      v.moveToFrame.length = 0;
      const lo = window.matlas.model.bounds.min, hi = window.matlas.model.bounds.max;
      for (let i = 0; i < 60; ++i) {
        await new Promise((r) => setTimeout(r, 16));
        const x = window.matlas.x.slice();
        x[0] = lo[0] + (hi[0] - lo[0]) * (0.2 + 0.01 * i);
        x[1] = lo[1] + (hi[1] - lo[1]) * (0.3 + 0.002 * i);
        map.point = x;
        map.redraw();
        map.cb.move(x, true, performance.now());
      }
      return { "reduced frame": med(gl.fastFrameTimes.slice(frames)), "move to frame": med(v.moveToFrame),
        bands: gl.fastBands };
    }, variant);
    console.log(`${variant}: ${Object.entries(result).map(([k, ms]) => `${k} ${k === "bands" ? ms : ms.toFixed(1) + " ms"}`).join(", ")}`);
    await page.close();
  }
} finally {
  await browser.close();
}
