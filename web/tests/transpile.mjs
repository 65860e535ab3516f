// Imports modules of web/src in node: each is transpiled with the TypeScript compiler (types
// dropped, nothing bundled) into a temporary folder, its relative imports pointed at the
// transpiled siblings. For tests of the page's plain logic without a browser.
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import ts from "typescript";
import { webDir } from "./server.mjs";

/** Transpiles web/src/NAME.ts for every name (with the modules they import among them); resolves to their exports by name. */
export async function importTs(names) {
  const out = mkdtempSync(join(tmpdir(), "matlas-ts-"));
  try {
    for (const name of names) {
      const source = readFileSync(join(webDir, "src", `${name}.ts`), "utf8");
      const js = ts.transpileModule(source, { compilerOptions: { module: ts.ModuleKind.ES2022, target: ts.ScriptTarget.ES2022 } })
        .outputText.replace(/from "\.\/([\w-]+)"/g, 'from "./$1.js"');
      writeFileSync(join(out, `${name}.js`), js);
    }
    const modules = {};
    for (const name of names) modules[name] = await import(join(out, `${name}.js`));
    return modules;
  } finally {
    rmSync(out, { recursive: true, force: true });
  }
}
