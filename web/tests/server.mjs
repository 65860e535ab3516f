// Starts `matlas demo` on a small synthetic database (16x16x32 grid, 128 px previews, 8 spp) on
// an ephemeral port in a temporary cache, for the node tests of this folder; opens the page in
// Debian's headless Chromium.
import { spawn } from "node:child_process";
import { join, resolve } from "node:path";
import { chromium } from "playwright-core";

export const webDir = resolve(import.meta.dirname, "..");
export const bin = resolve(process.env.MATLAS_BIN ?? join(webDir, "..", "build", "matlas"));

/** Resolves to { url, server } once the server prints its URL; `extra`: more flags of demo. */
export function startDemo(work, extra = []) {
  return new Promise((resolvePromise, reject) => {
    const server = spawn(bin, [
      "demo", "--grid", "16,16,32", "--size", "128", "--spp", "8", "--port", "0",
      "--cache", join(work, "cache"), "--web-root", join(webDir, "dist"), ...extra,
    ], { stdio: ["ignore", "pipe", "pipe"] });
    let out = "", err = "";
    const timer = setTimeout(() => reject(new Error(`matlas demo did not start:\n${out}\n${err}`)), 120_000);
    server.stdout.on("data", (d) => {
      out += d;
      const m = out.match(/open (http:\/\/\S+)/);
      if (m) {
        clearTimeout(timer);
        resolvePromise({ url: m[1], server });
      }
    });
    server.stderr.on("data", (d) => (err += d));
    server.on("exit", (code) => reject(new Error(`matlas demo exited (${code}):\n${out}\n${err}`)));
  });
}

/**
 * Stops a server started by startDemo and resolves once it has exited, so that its folder can be
 * removed: a server still writing a cache file (or removing its temporary on SIGTERM) while the
 * folder is removed made the removal fail with ENOTEMPTY.
 */
export function stopServer(server) {
  if (!server || server.exitCode !== null || server.signalCode !== null) return Promise.resolve();
  return new Promise((resolvePromise) => {
    const force = setTimeout(() => server.kill("SIGKILL"), 15_000);  // a server that does not stop
    server.once("exit", () => {
      clearTimeout(force);
      resolvePromise();
    });
    server.kill("SIGTERM");
  });
}

/**
 * Debian's Chromium (headless, through playwright-core; $CHROMIUM overrides the path) on `url`,
 * once the page shows its first preview. `args`: more browser flags; `onPage(page)` runs before
 * the page loads; other options go to launchPersistentContext. Resolves to { context, page }.
 */
export async function openPage(work, url, { args = [], onPage = () => {}, ...options } = {}) {
  const context = await chromium.launchPersistentContext(join(work, "profile"), {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    viewport: { width: 1440, height: 1000 },
    args: ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
      "--disable-component-update", "--disable-sync", ...args],
    ...options,
  });
  const page = context.pages()[0] ?? (await context.newPage());
  page.on("pageerror", (e) => console.error("page error:", e));
  onPage(page);
  await page.goto(url);
  await page.waitForFunction(() => window.matlas && window.matlas.previews >= 1, null, { timeout: 30_000 });
  return { context, page };
}
