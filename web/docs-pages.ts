// The reference docs as pages of the web UI: at build time every docs/*.md (and the README) is
// rendered to dist/docs/NAME.html with `marked`, its pictures copied beside it, so that the help
// dialog links to the docs of the very version being served (the server has no network and serves
// dist/ as it is). Links between docs become links between pages; links into the source tree
// (../src/...) become plain text, since the server does not serve sources; headings get GitHub's
// anchors so that "GI.md#the-scene-view" keeps working.
import { readdirSync, readFileSync, statSync } from "node:fs";
import { join, relative, resolve } from "node:path";
import { Marked, type Tokens } from "marked";
import type { Plugin } from "vite";

const repo = resolve(import.meta.dirname, "..");
const docsDir = join(repo, "docs");

/** GitHub's heading anchor: lower case, punctuation dropped, spaces to hyphens. */
export function slug(text: string): string {
  return text
    .toLowerCase()
    .replace(/<[^>]*>/g, "")
    .replace(/[^\p{L}\p{N}\s_-]/gu, "")
    .trim()
    .replace(/\s/g, "-");
}

function escapeHtml(s: string): string {
  return s.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c] ?? c);
}

/**
 * Where a link in a doc goes once the docs are pages: another doc's page (same anchor), a picture
 * beside it, an external address as is, or nothing (a file of the source tree).
 */
export function pageHref(href: string, fromReadme: boolean): string | null {
  if (/^[a-z]+:/i.test(href) || href.startsWith("#")) return href;
  const cut = href.indexOf("#");
  const path = cut < 0 ? href : href.slice(0, cut);
  const anchor = cut < 0 ? "" : href.slice(cut);
  let inDocs: string;
  if (fromReadme) {
    if (path === "README.md") return `README.html${anchor}`;
    if (!path.startsWith("docs/")) return null;
    inDocs = path.slice("docs/".length);
  } else {
    if (path === "../README.md") return `README.html${anchor}`;
    if (path.startsWith("../") || path.startsWith("/")) return null;
    inDocs = path.replace(/^\.\//, "");
  }
  if (inDocs.endsWith(".md")) return inDocs.includes("/") ? null : `${inDocs.slice(0, -3)}.html${anchor}`;
  return inDocs + anchor; // a picture or data file under docs/
}

function docNames(): string[] {
  return readdirSync(docsDir)
    .filter((f) => f.endsWith(".md"))
    .map((f) => f.slice(0, -3))
    .sort();
}

function render(markdown: string, title: string, fromReadme: boolean, names: string[]): string {
  const marked = new Marked({ gfm: true });
  const seen = new Map<string, number>();
  marked.use({
    renderer: {
      heading(this: { parser: { parseInline(t: Tokens.Generic[]): string } }, token: Tokens.Heading) {
        const inner = this.parser.parseInline(token.tokens);
        let id = slug(token.text);
        const k = seen.get(id) ?? 0;
        seen.set(id, k + 1);
        if (k > 0) id = `${id}-${k}`;
        return `<h${token.depth} id="${id}">${inner}</h${token.depth}>\n`;
      },
      link(this: { parser: { parseInline(t: Tokens.Generic[]): string } }, token: Tokens.Link) {
        const inner = this.parser.parseInline(token.tokens);
        const href = pageHref(token.href, fromReadme);
        if (href === null) return `<span class="source-link" title="${escapeHtml(token.href)}">${inner}</span>`;
        return `<a href="${escapeHtml(href)}">${inner}</a>`;
      },
      image(token: Tokens.Image) {
        const href = pageHref(token.href, fromReadme) ?? token.href;
        return `<img src="${escapeHtml(href)}" alt="${escapeHtml(token.text)}" loading="lazy">`;
      },
    },
  });
  const body = marked.parse(markdown, { async: false }) as string;
  const nav = ["README", ...names]
    .map((n) => `<a href="${n}.html"${n === title ? ' aria-current="page"' : ""}>${n === "README" ? "overview" : n}</a>`)
    .join(" ");
  return `<!doctype html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>matlas · ${escapeHtml(title)}</title>
<style>
body { font: 15px/1.55 system-ui, sans-serif; margin: 0; color: #1d2330; background: #fafbfc; }
nav { position: sticky; top: 0; background: #20262f; padding: 6px 16px; font-size: 13px; }
nav a { color: #c9d4e3; margin-right: 10px; text-decoration: none; white-space: nowrap; }
nav a[aria-current] { color: #fff; font-weight: 600; }
main { max-width: 980px; margin: 0 auto; padding: 8px 24px 48px; }
pre, code { font: 13px/1.4 ui-monospace, monospace; background: #eef1f5; }
pre { padding: 10px; overflow-x: auto; } code { padding: 0 3px; } pre code { padding: 0; }
table { border-collapse: collapse; display: block; overflow-x: auto; font-size: 13px; }
th, td { border: 1px solid #d5dbe3; padding: 3px 7px; vertical-align: top; }
img { max-width: 100%; } .source-link { border-bottom: 1px dotted #889; }
</style></head>
<body><nav><a href="../">← matlas browser</a> ${nav}</nav><main>
${body}</main></body></html>
`;
}

function filesUnder(dir: string): string[] {
  return readdirSync(dir).flatMap((f) => {
    const p = join(dir, f);
    return statSync(p).isDirectory() ? filesUnder(p) : [p];
  });
}

/** The Vite plugin: emits docs/NAME.html, docs/README.html and docs' other files into the build. */
export function docsPages(): Plugin {
  return {
    name: "matlas-docs-pages",
    apply: "build",
    generateBundle() {
      const names = docNames();
      for (const name of names) {
        const md = readFileSync(join(docsDir, `${name}.md`), "utf8");
        this.emitFile({ type: "asset", fileName: `docs/${name}.html`, source: render(md, name, false, names) });
      }
      const readme = readFileSync(join(repo, "README.md"), "utf8");
      this.emitFile({ type: "asset", fileName: "docs/README.html", source: render(readme, "README", true, names) });
      for (const file of filesUnder(docsDir).filter((f) => !f.endsWith(".md"))) {
        this.emitFile({ type: "asset", fileName: `docs/${relative(docsDir, file)}`, source: readFileSync(file) });
      }
    },
  };
}
