// The all-pairs definitions of the map's label declutter (web/src/labels.ts replaces them with a
// grid-bucketed placement and a sweep): the reference the unit test compares with and the
// baseline bench/label_layout_timing.mjs times.
export function placeLabelsAllPairs(labels, width, height, r, { labelCandidates, overlaps }, gap = 3) {
  const out = labels.map(() => null);
  const order = labels.map((_, i) => i).sort((a, b) => labels[b].priority - labels[a].priority || a - b);
  const markers = labels.map((l) => ({ x0: l.x - r, y0: l.y - r, x1: l.x + r, y1: l.y + r }));
  const placed = [];
  for (const i of order) {
    for (const c of labelCandidates(labels[i], r, gap)) {
      if (c.x0 < 0 || c.y0 < 0 || c.x1 > width || c.y1 > height) continue;
      if (placed.some((p) => overlaps(c, p))) continue;
      if (markers.some((m, k) => k !== i && overlaps(c, m))) continue;
      out[i] = c;
      placed.push(c);
      break;
    }
  }
  return out;
}

export function isolationAllPairs(xs, ys) {
  return xs.map((x, i) => {
    let d = Infinity;
    for (let j = 0; j < xs.length; j++) if (j !== i) d = Math.min(d, Math.hypot(x - xs[j], ys[i] - ys[j]));
    return Number.isNaN(d) ? Infinity : d;
  });
}
