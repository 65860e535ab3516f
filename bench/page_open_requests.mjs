// What the page asks for while it opens, and when each answer arrives, in a real browser
// (Debian's Chromium, headless, through playwright-core) on a running `matlas serve`: one line
// per API request (start -> end in ms after navigation; thumbnails counted, not listed), for
// `seconds` seconds.
//
//   node bench/page_open_requests.mjs http://127.0.0.1:8080/ [seconds=8]
import { openChromium } from "./chromium.mjs";

const url = process.argv[2] ?? "http://127.0.0.1:8080/";
const seconds = Number(process.argv[3] ?? 8);
const { page, close } = await openChromium({ viewport: { width: 1440, height: 1000 } });
try {
  const t0 = Date.now();
  const started = new Map();
  let thumbnails = 0, lastThumbnail = 0;
  page.on("request", (r) => {
    if (r.url().includes("/api/")) started.set(r, Date.now() - t0);
  });
  page.on("requestfinished", (r) => {
    if (!started.has(r)) return;
    const u = new URL(r.url());
    if (u.pathname.startsWith("/api/thumbnail")) {
      thumbnails += 1;
      lastThumbnail = Date.now() - t0;
      return;
    }
    const body = (r.postData() ?? "").slice(0, 40);
    console.log(`${String(started.get(r)).padStart(6)} -> ${String(Date.now() - t0).padStart(6)} ms  ${r.method()} ${u.pathname}${u.search.slice(0, 40)} ${body}`);
  });
  await page.goto(url);
  await page.waitForTimeout(seconds * 1000);
  console.log(`thumbnails: ${thumbnails}, the last at ${lastThumbnail} ms`);
} finally {
  await close();
}
