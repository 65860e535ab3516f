// The reference docs as pages (web/docs-pages.ts, built into web/dist/docs by `npm run build`):
// every doc and the README has a page, and every link or picture of every page resolves to a file
// of the build (and its anchor to a heading of that page), so the help dialog never leads to a 404.
//
//   npm run build && node --test tests/docs-pages.test.mjs
import { test } from "node:test";
import assert from "node:assert/strict";
import { existsSync, readdirSync, readFileSync } from "node:fs";
import { dirname, join, resolve } from "node:path";

const web = resolve(import.meta.dirname, "..");
const dist = join(web, "dist");
const built = join(dist, "docs");
const sources = readdirSync(join(web, "..", "docs")).filter((f) => f.endsWith(".md"));

const pages = () => readdirSync(built).filter((f) => f.endsWith(".html"));
const ids = (html) => new Set([...html.matchAll(/ id="([^"]+)"/g)].map((m) => m[1]));

test("every doc and the README is a page", () => {
  assert.ok(existsSync(built), "web/dist/docs exists (run npm run build first)");
  const have = new Set(pages());
  for (const md of [...sources, "README.md"]) assert.ok(have.has(md.replace(/\.md$/, ".html")), `${md} has a page`);
});

test("every link and picture of every page resolves, anchors included", () => {
  const broken = [];
  let checked = 0;
  for (const page of pages()) {
    const html = readFileSync(join(built, page), "utf8");
    for (const [, attr, target] of html.matchAll(/ (href|src)="([^"]*)"/g)) {
      if (/^[a-z]+:/i.test(target)) continue; // an external address
      const cut = target.indexOf("#");
      const path = cut < 0 ? target : target.slice(0, cut);
      const anchor = cut < 0 ? "" : decodeURIComponent(target.slice(cut + 1));
      const file = path === "" ? join(built, page) : resolve(built, path === "../" ? "../index.html" : path);
      checked++;
      if (!file.startsWith(dist) || !existsSync(file)) {
        broken.push(`${page}: ${attr}="${target}" (no such file)`);
      } else if (anchor && file.endsWith(".html") && !ids(readFileSync(file, "utf8")).has(anchor)) {
        broken.push(`${page}: ${attr}="${target}" (no heading #${anchor} in ${dirname(file) === built ? "" : "../"}${file.split("/").pop()})`);
      }
    }
  }
  assert.ok(checked > 100, `links checked: ${checked}`);
  assert.deepEqual(broken, []);
});

test("links into the source tree are text, not dead links", () => {
  const html = readFileSync(join(built, "README.html"), "utf8");
  assert.doesNotMatch(html, /href="(?:\.\.\/)*(?:src|scripts|bench|tests)\//, "no link into the sources");
});
