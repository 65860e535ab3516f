// Label declutter for the latent map: the same greedy placement as `matlas map`
// (src/render/label_layout.cpp). Labels are taken in priority order (the most isolated marker
// first, so that a crowded cluster shows one or two names and every isolated material keeps its
// own); each tries right, left, above, below and then the four diagonals of its marker and takes
// the first position whose box overlaps no label already placed, no other marker, and stays inside
// the canvas. The others are hidden: the map shows a hidden label on hover, and zooming in spreads the markers so that more fit.

export interface Box {
  x0: number;
  y0: number;
  x1: number;
  y1: number;
}

export interface LabelRequest {
  /** Marker centre (CSS pixels). */
  x: number;
  y: number;
  width: number;
  height: number;
  priority: number;
}

export function overlaps(a: Box, b: Box): boolean {
  return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

/** Boxes of the placed labels (null: hidden), in the order of `labels`. */
export function placeLabels(labels: LabelRequest[], width: number, height: number, markerRadius: number, gap = 3): (Box | null)[] {
  const out: (Box | null)[] = labels.map(() => null);
  const order = labels.map((_, i) => i).sort((a, b) => labels[b].priority - labels[a].priority || a - b);
  const markers: Box[] = labels.map((l) => ({
    x0: l.x - markerRadius, y0: l.y - markerRadius, x1: l.x + markerRadius, y1: l.y + markerRadius,
  }));
  const placed: Box[] = [];
  const off = markerRadius + gap;
  for (const i of order) {
    const l = labels[i];
    const d = 0.7 * off;
    const candidates: Box[] = [
      { x0: l.x + off, y0: l.y - l.height / 2, x1: l.x + off + l.width, y1: l.y + l.height / 2 },
      { x0: l.x - off - l.width, y0: l.y - l.height / 2, x1: l.x - off, y1: l.y + l.height / 2 },
      { x0: l.x - l.width / 2, y0: l.y - off - l.height, x1: l.x + l.width / 2, y1: l.y - off },
      { x0: l.x - l.width / 2, y0: l.y + off, x1: l.x + l.width / 2, y1: l.y + off + l.height },
      { x0: l.x + d, y0: l.y - d - l.height, x1: l.x + d + l.width, y1: l.y - d },
      { x0: l.x + d, y0: l.y + d, x1: l.x + d + l.width, y1: l.y + d + l.height },
      { x0: l.x - d - l.width, y0: l.y - d - l.height, x1: l.x - d, y1: l.y - d },
      { x0: l.x - d - l.width, y0: l.y + d, x1: l.x - d, y1: l.y + d + l.height },
    ];
    for (const c of candidates) {
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

/** Distance from each point to its nearest neighbour (the isolated first). */
export function isolation(xs: number[], ys: number[]): number[] {
  return xs.map((x, i) => {
    let d = Infinity;
    for (let j = 0; j < xs.length; j++) if (j !== i) d = Math.min(d, Math.hypot(x - xs[j], ys[i] - ys[j]));
    return d;
  });
}
