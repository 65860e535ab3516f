// The benchmarks' browser: Debian's Chromium (or $CHROMIUM), headless, through playwright-core
// (resolved from web/node_modules), in a fresh profile that close() removes.
//
//   const { page, close } = await openChromium({ viewport: { width: 1440, height: 1000 } });
//   try { ... } finally { await close(); }
//
// `webgl`: software WebGL2 through SwiftShader (the real-time view), else no GPU at all.
import { createRequire } from "node:module";
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";

const require = createRequire(resolve(import.meta.dirname, "..", "web", "package.json"));
const { chromium } = require("playwright-core");

const QUIET = ["--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update",
  "--disable-sync"];

export async function openChromium({ viewport, webgl = false }) {
  const profile = mkdtempSync(join(tmpdir(), "matlas-bench-"));
  const gpu = webgl ? ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"] : ["--disable-gpu"];
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium", headless: true, viewport,
    args: ["--no-sandbox", ...gpu, ...QUIET],
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { context, page, close };
}
