// The real-time view in a real browser (Debian's Chromium, headless, software WebGL2 through
// SwiftShader, 512 x 512 canvas) against a running `matlas serve`/`matlas demo`: the load time
// of the coefficients and of an environment's maps, the frame time distribution (each frame
// waited for with a 1-pixel readPixels) with the full L, its reduced frames drawn while the user
// moves, and with fewer bands, and the time from a
// pointer move on the map to the frame showing the new material (drags at 60 events per second).
//
//   node bench/realtime_viewer.mjs http://127.0.0.1:8080/ [frames=40]
//   (URL?weights=server: the page asks the server for the weights per move instead of computing them)
//
// The full frames take seconds with software WebGL; the viewer draws them in tiles between
// pointer events, so the scripted drags below run while tiles are pending.
import { openChromium } from "./chromium.mjs";

const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const frames = Number(process.argv[3] ?? 40);
const { page, close } = await openChromium({ viewport: { width: 1440, height: 1400 }, webgl: true });
const pct = (v) => {
  const s = [...v].sort((a, b) => a - b);
  const at = (p) => s[Math.min(s.length - 1, Math.floor(p * s.length))];
  return `n ${s.length}, min ${s[0].toFixed(1)}, p10 ${at(0.1).toFixed(1)}, median ${at(0.5).toFixed(1)}, p90 ${at(0.9).toFixed(1)}, max ${s[s.length - 1].toFixed(1)} ms`;
};
try {
  page.on("crash", () => console.error("the page crashed"));
  page.on("console", (m) => m.type() === "error" && console.error("page:", m.text()));
  const t0 = Date.now();
  await page.goto(url);
  await page.waitForFunction(() => window.matlasViewer && window.matlasViewer.gl.frameTimes.length > 0, null, { timeout: 600_000 });
  console.log(`page to first real-time frame: ${((Date.now() - t0) / 1000).toFixed(1)} s`);
  const loads = await page.evaluate(() => ({ ...window.matlasViewer.loads, info: window.matlasViewer.info.seconds,
    L: window.matlasViewer.info.bands, K: window.matlasViewer.info.coefficients, n: window.matlasViewer.info.materials,
    floatLinear: window.matlasViewer.gl.floatLinear }));
  console.log(`n = ${loads.n}, L = ${loads.L} (K = ${loads.K}), float32 linear textures: ${loads.floatLinear}`);
  console.log(`coefficients: computed by the server in ${loads.info.toFixed(2)} s; fetched by the page in ${loads.coefficientsMs.toFixed(0)} ms`);
  console.log(`environment maps fetched in: ${JSON.stringify(loads.environmentMs)} ms`);
  // Modes: the full frame (every band, full resolution) drawn at once, the reduced frames drawn
  // while orbiting, rotating or dragging (a quarter of the side; the viewer adapts their bands to
  // its budget, here also fixed at 8, 4, 2), and the full frame as the viewer draws it after an
  // interaction: in tiles over a few hundred animation frames.
  const modes = [["full", loads.L, false, Math.max(4, frames >> 3)], ["reduced, adaptive bands (the viewer's)", null, true, frames],
    ["reduced", 8, true, frames], ["reduced", 4, true, frames], ["reduced", 2, true, frames]];
  for (const [name, bands, fast, count] of modes) {
    const { times, used } = await page.evaluate(({ count, bands, fast, L }) => {
      const { gl } = window.matlasViewer;
      gl.setBands(L);
      gl.adaptive = bands === null;
      if (bands !== null) gl.fastBands = bands;
      gl.draw(fast);
      const times = [], used = [];
      for (let i = 0; i < count; ++i) {
        gl.camera.position.applyAxisAngle({ x: 0, y: 1, z: 0, isVector3: true }, 0.02);
        gl.camera.lookAt(0, 0, 0);
        used.push(Math.min(gl.fastBands, L));
        times.push(gl.draw(fast));
      }
      gl.adaptive = true;
      return { times, used };
    }, { count, bands, fast, L: loads.L });
    const bandsUsed = fast ? `, bands 0..${[...new Set(used)].sort((a, b) => a - b).join("/")}` : "";
    console.log(`frame time, ${name}, L = ${loads.L}${bandsUsed}: ${pct(times)}`);
  }
  for (let r = 0; r < 2; ++r) {
    const { tiles, wall } = await page.evaluate(async () => {
      const { gl } = window.matlasViewer;
      const before = gl.frameTimes.length;
      const start = performance.now();
      gl.setExposure(0);  // a change: a reduced frame, then the full one in tiles
      while (gl.frameTimes.length === before) await new Promise((r) => setTimeout(r, 20));
      return { tiles: gl.frameTimes[gl.frameTimes.length - 1], wall: performance.now() - start };
    });
    console.log(`full frame in tiles after a change: ${(tiles / 1000).toFixed(2)} s drawing, ${(wall / 1000).toFixed(2)} s until complete`);
  }
  await page.evaluate((L) => {
    const { gl } = window.matlasViewer;
    gl.setBands(L);
    gl.resetCamera();
  }, loads.L);
  await page.waitForTimeout(1000);
  try {
    await page.evaluate((L) => window.matlasViewer.gl.setBands(L), loads.L);
    const box = await page.locator("#map").boundingBox();
    await page.evaluate(() => (window.matlasViewer.moveToFrame.length = window.matlasViewer.moveToFrameReduced.length = 0));
    for (let d = 0; d < 3; ++d) {
      await page.mouse.move(box.x + box.width * 0.2, box.y + box.height * (0.3 + 0.2 * d));
      await page.mouse.down();
      for (let i = 1; i <= 60; ++i) {
        await page.mouse.move(box.x + box.width * (0.2 + 0.01 * i), box.y + box.height * (0.3 + 0.2 * d + 0.002 * i));
        await page.waitForTimeout(16);
      }
      await page.mouse.up();
      await page.waitForTimeout(500);
    }
    const { lat, reduced } = await page.evaluate(() => ({ lat: window.matlasViewer.moveToFrame, reduced: window.matlasViewer.moveToFrameReduced }));
    console.log(`pointer move to frame (every frame with new coefficients during 3 drags of 60 moves): ${pct(lat)}`);
    const during = lat.filter((_, i) => reduced[i]);
    if (during.length) console.log(`  of which reduced frames (drawn while the pointer is down): ${pct(during)}`);
    const after = lat.filter((_, i) => !reduced[i]);
    if (after.length) console.log(`  of which full frames (the point reached after the pointer was released): ${pct(after)}`);
  } catch (e) {
    console.log(`pointer move to frame: not measured (${e.message.split("\n")[0]})`);
  }
} finally {
  await close();
}
