// Writes the Utah teapot of three.js (TeapotGeometry: Bezier patches, tessellated) as a Wavefront
// OBJ with per-vertex normals, for the path tracer's scenes (docs/GI.md).
//
//   node scripts/teapot-obj.mjs THREE_PACKAGE_DIR OUTPUT.obj
import { writeFileSync, renameSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [threeDir, output] = process.argv.slice(2);
if (!threeDir || !output) {
  console.error('usage: node teapot-obj.mjs THREE_PACKAGE_DIR OUTPUT.obj');
  process.exit(2);
}
const module = join(threeDir, 'examples/jsm/geometries/TeapotGeometry.js');
const { TeapotGeometry } = await import(pathToFileURL(module).href);
// size 1, 12 segments per patch, with bottom, lid and body, the lid fitted, Blinn's proportions.
const geometry = new TeapotGeometry(1, 12, true, true, true, true, true);
const position = geometry.getAttribute('position');
const normal = geometry.getAttribute('normal');
const index = geometry.getIndex();
const lines = ['# Utah teapot (three.js TeapotGeometry)'];
for (let i = 0; i < position.count; ++i) lines.push(`v ${position.getX(i)} ${position.getY(i)} ${position.getZ(i)}`);
for (let i = 0; i < normal.count; ++i) lines.push(`vn ${normal.getX(i)} ${normal.getY(i)} ${normal.getZ(i)}`);
for (let t = 0; t < index.count; t += 3) {
  const [a, b, c] = [index.getX(t) + 1, index.getX(t + 1) + 1, index.getX(t + 2) + 1];
  lines.push(`f ${a}//${a} ${b}//${b} ${c}//${c}`);
}
const tmp = `${output}.tmp-${process.pid}`;
writeFileSync(tmp, lines.join('\n') + '\n');
renameSync(tmp, output);
console.error(`teapot: ${position.count} vertices, ${index.count / 3} triangles in ${output}`);
