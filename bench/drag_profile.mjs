// Where a map drag's time goes in the page (docs/BENCHMARKS.md, "Real-time viewer"): one drag of
// 90 pointer moves at most every 16 ms on the map of a running `matlas serve`/`matlas demo`, in
// Debian's headless Chromium (through playwright-core), then: the drag's length and the previews'
// pointer-to-image median, the real-time view's reduced frames (count, median, sum, bands,
// lights), the long tasks, the API requests made during the drag by endpoint, and the main
// thread's JavaScript profile by self time (CDP Profiler; "(program)" is native work).
//
//   node bench/drag_profile.mjs http://127.0.0.1:8080/
//   BLOCK_REALTIME=1 node bench/drag_profile.mjs URL   the real-time card's requests refused
//   NO_PROFILE=1 node bench/drag_profile.mjs URL       without the profiler's overhead
import { openChromium } from "./chromium.mjs";

const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const { page, close } = await openChromium({ viewport: { width: 1440, height: 1000 } });
const median = (v) => [...v].sort((a, b) => a - b)[v.length >> 1];
try {
  const requests = {};
  page.on("request", (r) => {
    const path = new URL(r.url()).pathname;
    if (path.startsWith("/api/")) requests[`${r.method()} ${path}`] = (requests[`${r.method()} ${path}`] ?? 0) + 1;
  });
  if (process.env.BLOCK_REALTIME) await page.route("**/api/realtime**", (r) => r.abort());
  await page.goto(url);
  await page.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 60_000 });
  await page.waitForTimeout(4000);  // the real-time card's loading
  await page.evaluate(() => {
    window.benchLongTasks = [];
    new PerformanceObserver((l) => { for (const e of l.getEntries()) window.benchLongTasks.push(e.duration); })
      .observe({ type: "longtask" });
    window.matlas.latencies.length = 0;
  });
  for (const k of Object.keys(requests)) delete requests[k];
  const cdp = await page.context().newCDPSession(page);
  const profiling = !process.env.NO_PROFILE;
  if (profiling) {
    await cdp.send("Profiler.enable");
    await cdp.send("Profiler.setSamplingInterval", { interval: 200 });
    await cdp.send("Profiler.start");
  }
  const box = await page.locator("#map").boundingBox();
  const t0 = Date.now();
  await page.mouse.move(box.x + box.width * 0.15, box.y + box.height * 0.3);
  await page.mouse.down();
  for (let k = 0; k <= 90; k++) {
    await page.mouse.move(box.x + box.width * (0.15 + 0.008 * k), box.y + box.height * (0.3 + 0.002 * k));
    await page.waitForTimeout(16);
  }
  await page.mouse.up();
  const dragMs = Date.now() - t0;
  const profile = profiling ? (await cdp.send("Profiler.stop")).profile : null;
  await page.waitForTimeout(300);
  const latencies = await page.evaluate(() => window.matlas.latencies.slice());
  const longTasks = await page.evaluate(() => window.benchLongTasks);
  console.log(`drag of 91 moves: ${dragMs} ms; ${latencies.length} previews, pointer-to-image median ${median(latencies)?.toFixed(1)} ms`);
  const rt = await page.evaluate(() => {
    const g = window.matlasViewer?.gl;
    return g && { frames: g.dragFrames.map((f) => f.ms), bands: g.fastBands, lights: g.fastLights };
  });
  console.log(rt ? `real-time view: ${rt.frames.length} reduced frames in all, median ${median(rt.frames)?.toFixed(1)} ms, ` +
    `sum ${rt.frames.reduce((a, b) => a + b, 0).toFixed(0)} ms, bands 0..${rt.bands}, ${rt.lights} lights` : "no real-time view");
  console.log(`long tasks: ${longTasks.length}, ${longTasks.reduce((a, b) => a + b, 0).toFixed(0)} ms`);
  console.log(`requests during the drag: ${JSON.stringify(requests)}`);
  if (profile) {
    const byId = new Map(profile.nodes.map((n) => [n.id, n]));
    const self = new Map();
    profile.samples.forEach((id, i) => {
      const f = byId.get(id).callFrame;
      const key = `${f.functionName || "(anonymous)"} ${f.url.split("/").pop()}`;
      self.set(key, (self.get(key) ?? 0) + (profile.timeDeltas[i] ?? 0));
    });
    console.log("main thread, self time:");
    [...self.entries()].sort((a, b) => b[1] - a[1]).slice(0, 12)
      .forEach(([k, us]) => console.log(`${(us / 1000).toFixed(0).padStart(8)} ms  ${k}`));
  }
} finally {
  await close();
}
