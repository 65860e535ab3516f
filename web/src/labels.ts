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

/**
 * Boxes bucketed by the cells of a uniform grid over the canvas that they overlap (boxes reaching
 * outside are clamped to the border cells): a query tests only the boxes of the cells it covers,
 * so placing n labels among n markers does not cost n^2 tests (src/render/label_layout.cpp does the same).
 */
class BoxGrid {
  private readonly cols: number;
  private readonly rows: number;
  private readonly sx: number;
  private readonly sy: number;
  private readonly cells: number[][];

  constructor(width: number, height: number) {
    const count = (extent: number) => (extent > 0 ? Math.min(256, Math.max(1, Math.ceil(extent / 32))) : 1);
    this.cols = count(width);
    this.rows = count(height);
    this.sx = width > 0 ? this.cols / width : 0;
    this.sy = height > 0 ? this.rows / height : 0;
    this.cells = Array.from({ length: this.cols * this.rows }, () => []);
  }

  private static cell(v: number, scale: number, count: number): number {
    const c = Math.floor(v * scale);
    if (!(c > 0)) return 0;
    return c >= count - 1 ? count - 1 : c;
  }

  private range(b: Box): [number, number, number, number] {
    return [BoxGrid.cell(b.x0, this.sx, this.cols), BoxGrid.cell(b.x1, this.sx, this.cols),
      BoxGrid.cell(b.y0, this.sy, this.rows), BoxGrid.cell(b.y1, this.sy, this.rows)];
  }

  insert(b: Box, id: number): void {
    const [i0, i1, j0, j1] = this.range(b);
    for (let j = j0; j <= j1; j++) for (let i = i0; i <= i1; i++) this.cells[j * this.cols + i].push(id);
  }

  /** Whether `b` overlaps a stored box other than `skip`, boxes[] holding them by id. */
  overlapsAny(b: Box, boxes: Box[], skip = -1): boolean {
    const [i0, i1, j0, j1] = this.range(b);
    for (let j = j0; j <= j1; j++)
      for (let i = i0; i <= i1; i++)
        for (const k of this.cells[j * this.cols + i]) if (k !== skip && overlaps(b, boxes[k])) return true;
    return false;
  }
}

/** Boxes of the placed labels (null: hidden), in the order of `labels`. */
/** The eight places tried for a label, in order: right, left, above, below, then the diagonals;
 *  `gap` pixels beyond a marker of radius `markerRadius`. */
export function labelCandidates(l: LabelRequest, markerRadius: number, gap = 3): Box[] {
  const off = markerRadius + gap, d = 0.7 * off;
  return [
    { x0: l.x + off, y0: l.y - l.height / 2, x1: l.x + off + l.width, y1: l.y + l.height / 2 },
    { x0: l.x - off - l.width, y0: l.y - l.height / 2, x1: l.x - off, y1: l.y + l.height / 2 },
    { x0: l.x - l.width / 2, y0: l.y - off - l.height, x1: l.x + l.width / 2, y1: l.y - off },
    { x0: l.x - l.width / 2, y0: l.y + off, x1: l.x + l.width / 2, y1: l.y + off + l.height },
    { x0: l.x + d, y0: l.y - d - l.height, x1: l.x + d + l.width, y1: l.y - d },
    { x0: l.x + d, y0: l.y + d, x1: l.x + d + l.width, y1: l.y + d + l.height },
    { x0: l.x - d - l.width, y0: l.y - d - l.height, x1: l.x - d, y1: l.y - d },
    { x0: l.x - d - l.width, y0: l.y + d, x1: l.x - d, y1: l.y + d + l.height },
  ];
}

export function placeLabels(labels: LabelRequest[], width: number, height: number, markerRadius: number, gap = 3): (Box | null)[] {
  const out: (Box | null)[] = labels.map(() => null);
  const order = labels.map((_, i) => i).sort((a, b) => labels[b].priority - labels[a].priority || a - b);
  const markers: Box[] = labels.map((l) => ({
    x0: l.x - markerRadius, y0: l.y - markerRadius, x1: l.x + markerRadius, y1: l.y + markerRadius,
  }));
  const markerGrid = new BoxGrid(width, height), labelGrid = new BoxGrid(width, height);
  markers.forEach((m, i) => markerGrid.insert(m, i));
  const placed: Box[] = [];
  for (const i of order) {
    const l = labels[i];
    const candidates = labelCandidates(l, markerRadius, gap);
    for (const c of candidates) {
      if (c.x0 < 0 || c.y0 < 0 || c.x1 > width || c.y1 > height) continue;
      if (labelGrid.overlapsAny(c, placed) || markerGrid.overlapsAny(c, markers, i)) continue;
      out[i] = c;
      labelGrid.insert(c, placed.length);
      placed.push(c);
      break;
    }
  }
  return out;
}

/**
 * Distance from each point to its nearest neighbour (the isolated first). A sweep in x order: from
 * each point, walk left and right until the x gap alone exceeds the nearest distance found (about
 * n sqrt(n) distances for points spread over the plane, not n^2). NaN coordinates: nobody's neighbour.
 */
export function isolation(xs: number[], ys: number[]): number[] {
  const n = Math.min(xs.length, ys.length);
  const d: number[] = new Array(n).fill(Infinity);
  const order = Array.from({ length: n }, (_, i) => i).sort((a, b) =>
    Number.isNaN(xs[a]) ? (Number.isNaN(xs[b]) ? a - b : 1) : Number.isNaN(xs[b]) ? -1 : xs[a] - xs[b] || a - b);
  for (let s = 0; s < n; s++) {
    const i = order[s];
    let best = Infinity;
    for (let t = s + 1; t < n && xs[order[t]] - xs[i] < best; t++) {
      const h = Math.hypot(xs[i] - xs[order[t]], ys[i] - ys[order[t]]);
      if (h < best) best = h;
    }
    for (let t = s - 1; t >= 0 && xs[i] - xs[order[t]] < best; t--) {
      const h = Math.hypot(xs[i] - xs[order[t]], ys[i] - ys[order[t]]);
      if (h < best) best = h;
    }
    d[i] = best;
  }
  return d;
}
