// docs/api.schema.json in the node tests: a validator for the JSON Schema subset it uses ($ref,
// anyOf, type, enum, properties/required/additionalProperties, items, prefixItems, minItems), the
// same schemas in a normal form to compare with the TypeScript types of web/src/api.ts (read with
// the TypeScript compiler's parser), and the endpoints of docs/API.md.
import { readFileSync } from "node:fs";
import { join } from "node:path";
import ts from "typescript";
import { webDir } from "./server.mjs";

export const schemaPath = join(webDir, "..", "docs", "api.schema.json");
export const schema = JSON.parse(readFileSync(schemaPath, "utf8"));

const refName = (ref) => ref.replace("#/$defs/", "");

/** Problems of `value` against `node` (empty: valid), each with its JSON path. */
export function validate(value, node, path = "$") {
  if (node.$ref) return validate(value, schema.$defs[refName(node.$ref)], path);
  if (node.anyOf) {
    const all = node.anyOf.map((n) => validate(value, n, path));
    return all.some((p) => p.length === 0) ? [] : all.flat();
  }
  const type = node.type;
  const typeOk = {
    null: value === null, boolean: typeof value === "boolean", string: typeof value === "string",
    number: typeof value === "number" && Number.isFinite(value), integer: Number.isInteger(value),
    array: Array.isArray(value), object: value !== null && typeof value === "object" && !Array.isArray(value),
  }[type];
  if (!typeOk) return [`${path}: expected ${type}, got ${JSON.stringify(value)?.slice(0, 40)}`];
  if (node.enum && !node.enum.includes(value)) return [`${path}: ${value} is not one of ${node.enum}`];
  const out = [];
  if (type === "array") {
    if (node.minItems !== undefined && value.length < node.minItems) out.push(`${path}: fewer than ${node.minItems} items`);
    const prefix = node.prefixItems ?? [];
    if (node.items === false && value.length > prefix.length) out.push(`${path}: more than ${prefix.length} items`);
    value.forEach((v, i) => {
      const item = i < prefix.length ? prefix[i] : node.items;
      if (item) out.push(...validate(v, item, `${path}[${i}]`));
    });
  }
  if (type === "object") {
    for (const k of node.required ?? []) if (!(k in value)) out.push(`${path}: missing "${k}"`);
    for (const [k, v] of Object.entries(value)) {
      const prop = node.properties?.[k];
      if (prop) out.push(...validate(v, prop, `${path}.${k}`));
      else if (node.additionalProperties === false) out.push(`${path}: unexpected "${k}"`);
    }
  }
  return out;
}

/** A schema node in the normal form shared with normalTs. */
export function normalSchema(node) {
  if (node.$ref) return { ref: refName(node.$ref) };
  if (node.anyOf) return { union: node.anyOf.map(normalSchema) };
  switch (node.type) {
    case "integer": case "number": return { kind: "number" };
    case "string": return node.enum ? { kind: "string", enum: [...node.enum].sort() } : { kind: "string" };
    case "boolean": case "null": return { kind: node.type };
    case "array": return node.prefixItems
      ? { kind: "tuple", items: node.prefixItems.map(normalSchema) }
      : { kind: "array", items: normalSchema(node.items) };
    case "object": return {
      kind: "object",
      props: Object.fromEntries(Object.entries(node.properties).map(([k, v]) =>
        [k, { optional: !(node.required ?? []).includes(k), type: normalSchema(v) }])),
    };
    default: throw new Error(`schema node without a known type: ${JSON.stringify(node)}`);
  }
}

/** The top-level interfaces and type aliases of a TypeScript file, in the normal form. */
export function normalTs(file) {
  const src = ts.createSourceFile(file, readFileSync(file, "utf8"), ts.ScriptTarget.ES2022, true);
  const members = (list) => ({
    kind: "object",
    props: Object.fromEntries(list.filter(ts.isPropertySignature).map((m) =>
      [m.name.getText(src), { optional: m.questionToken !== undefined, type: norm(m.type) }])),
  });
  const norm = (t) => {
    switch (t.kind) {
      case ts.SyntaxKind.NumberKeyword: return { kind: "number" };
      case ts.SyntaxKind.StringKeyword: return { kind: "string" };
      case ts.SyntaxKind.BooleanKeyword: return { kind: "boolean" };
      case ts.SyntaxKind.ArrayType: return { kind: "array", items: norm(t.elementType) };
      case ts.SyntaxKind.TupleType: return { kind: "tuple", items: t.elements.map(norm) };
      case ts.SyntaxKind.TypeLiteral: return members(t.members);
      case ts.SyntaxKind.TypeReference: return { ref: t.typeName.getText(src) };
      case ts.SyntaxKind.LiteralType:
        if (t.literal.kind === ts.SyntaxKind.NullKeyword) return { kind: "null" };
        if (ts.isStringLiteral(t.literal)) return { kind: "string", enum: [t.literal.text] };
        break;
      case ts.SyntaxKind.UnionType: {
        const parts = t.types.map(norm);
        if (parts.every((p) => p.enum)) return { kind: "string", enum: parts.flatMap((p) => p.enum).sort() };
        return { union: parts };
      }
    }
    throw new Error(`${file}: unsupported type ${t.getText(src)}`);
  };
  const types = {};
  for (const st of src.statements) {
    if (ts.isInterfaceDeclaration(st)) types[st.name.text] = members(st.members);
    else if (ts.isTypeAliasDeclaration(st)) types[st.name.text] = norm(st.type);
  }
  return types;
}

/** The endpoints documented in docs/API.md: "## `METHOD /api/...` -> `type`" headings and their text. */
export function documentedEndpoints(file) {
  const text = readFileSync(file, "utf8");
  const out = [];
  const re = /^## `(GET|POST) (\/api\/[^`?]+)[^`]*`(?: -> `([^`]+)`)?\n([\s\S]*?)(?=^## |$(?![\s\S]))/gm;
  for (const m of text.matchAll(re)) out.push({ method: m[1], path: m[2], type: m[3] ?? "application/json", text: m[4] });
  return out;
}
