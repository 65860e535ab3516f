// MapPainter: draws one frame of the latent map on its canvas (background layer and "no data
// here" hatching, grid, path, markers, decluttered labels, the projected upload, the fitted
// samples with their uncertainty ellipse, the current point) and says which labels it drew. It keeps the label widths and the hatch pattern between
// frames; the LatentMap (map.ts) owns the view and the interaction.
import { isolation, overlaps, placeLabels, type Box } from "./labels";
import { fmt, niceStep } from "./map-geometry";

export interface ViewRect {
  x0: number;
  x1: number;
  y0: number;
  y1: number;
}

export interface MapMarker {
  x: number[];
  label: string;
}

/** A fitted sample file: its point and the 2-sigma ellipse of its latent covariance. */
export interface FitMarker {
  x: number[];
  /** q x q covariance of x (null entries: undetermined); the displayed plane's 2 x 2 block is drawn. */
  covariance: (number | null)[][];
  label: string;
}

/** The fit's ellipse as drawn: centre and semi-axes in CSS pixels (2 sigma), axis angle in radians. */
export interface DrawnEllipse {
  cx: number;
  cy: number;
  rx: number;
  ry: number;
  angle: number;
}

/**
 * The 2-sigma ellipse of the (a, b) block of a covariance, in latent units: semi-axes 2 sqrt(lambda)
 * of the block's eigenvalues and the angle of the first axis; null when the block is not finite.
 */
export function sigmaEllipse(cov: (number | null)[][], a: number, b: number): { r1: number; r2: number; angle: number } | null {
  const saa = cov[a]?.[a], sbb = cov[b]?.[b], sab = cov[a]?.[b];
  if (saa == null || sbb == null || sab == null || ![saa, sbb, sab].every(Number.isFinite)) return null;
  const mean = 0.5 * (saa + sbb), diff = 0.5 * (saa - sbb);
  const root = Math.hypot(diff, sab);
  const l1 = Math.max(mean + root, 0), l2 = Math.max(mean - root, 0);
  return { r1: 2 * Math.sqrt(l1), r2: 2 * Math.sqrt(l2), angle: 0.5 * Math.atan2(2 * sab, saa - sbb) };
}

export interface MapPath {
  a: number[];
  b: number[];
  samples: number[][];
}

/** A background layer image over `rect`; `hatched`: "no data here" shows where it is transparent. */
export interface MapLayerImage {
  image: ImageBitmap;
  rect: ViewRect;
  hatched: boolean;
}

/** What a frame shows: the map's state, read by the painter. */
export interface MapFrame {
  readonly canvas: HTMLCanvasElement;
  readonly latent: number[][];
  readonly names: string[];
  readonly colors: [number, number, number][];
  readonly axes: [number, number];
  readonly point: number[];
  readonly showLabels: boolean;
  readonly path: MapPath | null;
  readonly projected: MapMarker | null;
  readonly fitted: FitMarker | null;
  readonly layer: MapLayerImage | null;
  readonly hovered: number | null;
  readonly view: ViewRect;
  /** The latent points' bounding box (scales the distance from the slice when q > 2). */
  readonly bounds: { min: number[]; max: number[] };
  toScreen(u: number, v: number): [number, number];
}

/** The labels a frame drew. */
export interface DrawnLabels {
  /** Decluttered labels (not the hovered one). */
  labelBoxes: { index: number; box: Box }[];
  /** Materials whose marker is inside the canvas. */
  visibleMaterials: number;
  /** The hovered material's label box when it was drawn on hover only. */
  hoverLabel: { index: number; box: Box } | null;
  /** Each material's marker opacity (1 for q = 2; q > 2: from its distance to the slice). */
  alpha: number[];
  /** The fitted samples' ellipse, when one is shown. */
  fitEllipse: DrawnEllipse | null;
}

/** Below this opacity (far from the displayed slice) a material gets no label unless hovered. */
export const LABEL_ALPHA = 0.5;

/**
 * Opacity of material i's marker: 1 on the displayed plane, fading with the distance of its other
 * coordinates from the current point's (each scaled by the latent points' extent on that axis):
 * 0.1 + 0.9 exp(-(d / 0.15)^2), so 0.68 at a tenth of the extent, 0.25 at a fifth, 0.1 beyond.
 */
export function sliceAlpha(p: number[], x: number[], axes: [number, number], bounds: { min: number[]; max: number[] }): number {
  let d2 = 0;
  for (let d = 0; d < p.length; d++) {
    if (d === axes[0] || d === axes[1]) continue;
    const span = Math.max(bounds.max[d] - bounds.min[d], 1e-9);
    d2 += ((p[d] - x[d]) / span) ** 2;
  }
  return 0.1 + 0.9 * Math.exp(-d2 / (0.15 * 0.15));
}

export class MapPainter {
  private widths = new Map<number, number>();
  private hatch: CanvasPattern | null = null;

  draw(m: MapFrame): DrawnLabels {
    const out: DrawnLabels = { labelBoxes: [], visibleMaterials: 0, hoverLabel: null, alpha: [], fitEllipse: null };
    const c = m.canvas;
    const dpr = window.devicePixelRatio || 1;
    const r = c.getBoundingClientRect();
    const w = Math.max(1, Math.round(r.width * dpr)), h = Math.max(1, Math.round(r.height * dpr));
    if (c.width !== w || c.height !== h) {
      c.width = w;
      c.height = h;
    }
    const g = c.getContext("2d")!;
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.fillStyle = "#101216";
    g.fillRect(0, 0, r.width, r.height);
    const [a, b] = m.axes;

    if (m.layer) {
      const { x0, x1, y0, y1 } = m.layer.rect;
      const [sx0, sy0] = m.toScreen(x0, y1);
      const [sx1, sy1] = m.toScreen(x1, y0);
      g.imageSmoothingEnabled = true;
      if (m.layer.hatched) {
        g.fillStyle = this.hatchPattern(g);
        g.fillRect(sx0, sy0, sx1 - sx0, sy1 - sy0);
      }
      g.globalAlpha = m.layer.hatched ? 1 : 0.9;  // the hatch must not show through the data
      g.drawImage(m.layer.image, sx0, sy0, sx1 - sx0, sy1 - sy0);
      g.globalAlpha = 1;
    }
    this.drawGrid(m, g, r.width, r.height);

    if (m.path) {
      const [ax, ay] = m.toScreen(m.path.a[a], m.path.a[b]);
      const [bx, by] = m.toScreen(m.path.b[a], m.path.b[b]);
      g.strokeStyle = "#f5c04a";
      g.lineWidth = 2;
      g.setLineDash([6, 4]);
      g.beginPath();
      g.moveTo(ax, ay);
      g.lineTo(bx, by);
      g.stroke();
      g.setLineDash([]);
      g.fillStyle = "#f5c04a";
      for (const s of m.path.samples) {
        const [sx, sy] = m.toScreen(s[a], s[b]);
        g.fillRect(sx - 2, sy - 2, 4, 4);
      }
    }

    g.font = "11px system-ui, sans-serif";
    g.textBaseline = "middle";
    // Markers inside the canvas, and their decluttered labels.
    const visible: number[] = [], xs: number[] = [], ys: number[] = [];
    out.alpha = m.latent.map((p) => (p.length > 2 ? sliceAlpha(p, m.point, m.axes, m.bounds) : 1));
    m.latent.forEach((p, i) => {
      const [sx, sy] = m.toScreen(p[a], p[b]);
      if (sx < -8 || sy < -8 || sx > r.width + 8 || sy > r.height + 8) return;
      visible.push(i);
      xs.push(sx);
      ys.push(sy);
    });
    out.visibleMaterials = visible.length;
    const labelHeight = 15;
    let boxes: (Box | null)[] = visible.map(() => null);
    if (m.showLabels) {
      const priority = isolation(xs, ys);
      // Materials far from the displayed slice (q > 2) get no label: they would name what is not there.
      boxes = placeLabels(
        visible.map((i, k) => ({ x: xs[k], y: ys[k], width: this.labelWidth(m, g, i), height: labelHeight,
          priority: out.alpha[i] < LABEL_ALPHA ? -1e9 : priority[k] })),
        r.width, r.height, 7);
      boxes = boxes.map((box, k) => (out.alpha[visible[k]] < LABEL_ALPHA ? null : box));
    }
    visible.forEach((i, k) => {
      const [sx, sy] = [xs[k], ys[k]];
      const [cr, cg, cb] = m.colors[i] ?? [200, 200, 200];
      g.globalAlpha = i === m.hovered ? 1 : out.alpha[i];
      g.beginPath();
      g.arc(sx, sy, i === m.hovered ? 7 : 5, 0, 2 * Math.PI);
      g.fillStyle = `rgb(${cr},${cg},${cb})`;
      g.fill();
      g.lineWidth = i === m.hovered ? 2 : 1;
      g.strokeStyle = i === m.hovered ? "#ffffff" : "rgba(255,255,255,0.55)";
      g.stroke();
    });
    g.globalAlpha = 1;
    visible.forEach((i, k) => {
      const box = boxes[k];
      if (!box) return;
      out.labelBoxes.push({ index: i, box });
      this.drawLabel(m, g, i, box, i === m.hovered ? "#ffffff" : "#c9ced8", false);
    });
    if (m.hovered !== null && !out.labelBoxes.some((l) => l.index === m.hovered)) {
      // A hidden label on hover: on top of the others, on a dark plate.
      const i = m.hovered;
      const [sx, sy] = m.toScreen(m.latent[i][a], m.latent[i][b]);
      const w = this.labelWidth(m, g, i);
      const x0 = sx + 10 + w > r.width ? sx - 10 - w : sx + 10;
      const box = { x0, y0: sy - labelHeight / 2, x1: x0 + w, y1: sy + labelHeight / 2 };
      out.hoverLabel = { index: i, box };
      this.drawLabel(m, g, i, box, "#ffffff", true);
    }

    if (m.projected) {
      const [sx, sy] = m.toScreen(m.projected.x[a], m.projected.x[b]);
      g.save();
      g.translate(sx, sy);
      g.rotate(Math.PI / 4);
      g.fillStyle = "#58d68d";
      g.strokeStyle = "#0b0c0f";
      g.lineWidth = 1.5;
      g.fillRect(-6, -6, 12, 12);
      g.strokeRect(-6, -6, 12, 12);
      g.restore();
      // Its name, unless it would cover a material's label (the status line names it too).
      const w = g.measureText(m.projected.label).width;
      const box = { x0: sx + 10, y0: sy - 17, x1: sx + 10 + w, y1: sy - 3 };
      if (!out.labelBoxes.some((l) => overlaps(l.box, box))) {
        g.fillStyle = "#58d68d";
        g.fillText(m.projected.label, sx + 10, sy - 10);
      }
    }

    if (m.fitted) out.fitEllipse = this.drawFit(m, g, m.fitted, out.labelBoxes.map((l) => l.box));

    const [px, py] = m.toScreen(m.point[a], m.point[b]);
    g.strokeStyle = "#ffffff";
    g.lineWidth = 2;
    g.beginPath();
    g.arc(px, py, 9, 0, 2 * Math.PI);
    g.stroke();
    g.strokeStyle = "#4aa3ff";
    g.beginPath();
    g.moveTo(px - 14, py); g.lineTo(px - 5, py);
    g.moveTo(px + 5, py); g.lineTo(px + 14, py);
    g.moveTo(px, py - 14); g.lineTo(px, py - 5);
    g.moveTo(px, py + 5); g.lineTo(px, py + 14);
    g.stroke();
    return out;
  }

  /** The fitted samples: a 2-sigma ellipse (filled lightly) around an orange triangle, and its label. */
  private drawFit(m: MapFrame, g: CanvasRenderingContext2D, f: FitMarker, labels: Box[]): DrawnEllipse {
    const [a, b] = m.axes;
    const [sx, sy] = m.toScreen(f.x[a], f.x[b]);
    const [ux] = m.toScreen(f.x[a] + 1, f.x[b]);
    const scale = ux - sx;  // CSS pixels per latent unit (the same on both axes)
    const e = sigmaEllipse(f.covariance, a, b);
    // An axis longer than the data's extent says "not pinned down along this direction" (the table
    // barely changes along it): drawn up to that length, not across the whole canvas.
    const cap = Math.max(m.bounds.max[a] - m.bounds.min[a], m.bounds.max[b] - m.bounds.min[b]) * scale;
    const drawn: DrawnEllipse = {
      cx: sx, cy: sy, rx: e ? Math.min(e.r1 * scale, cap) : 0, ry: e ? Math.min(e.r2 * scale, cap) : 0, angle: e ? e.angle : 0,
    };
    g.save();
    if (e) {
      g.beginPath();
      // Latent y points up, screen y down: the angle flips.
      g.ellipse(sx, sy, Math.max(drawn.rx, 1.5), Math.max(drawn.ry, 1.5), -drawn.angle, 0, 2 * Math.PI);
      g.fillStyle = "rgba(255, 159, 67, 0.18)";
      g.fill();
      g.strokeStyle = "#ff9f43";
      g.lineWidth = 1.5;
      g.setLineDash([5, 3]);
      g.stroke();
      g.setLineDash([]);
    }
    g.beginPath();
    g.moveTo(sx, sy - 8);
    g.lineTo(sx + 7, sy + 5);
    g.lineTo(sx - 7, sy + 5);
    g.closePath();
    g.fillStyle = "#ff9f43";
    g.strokeStyle = "#0b0c0f";
    g.lineWidth = 1.5;
    g.fill();
    g.stroke();
    const w = g.measureText(f.label).width;
    const box = { x0: sx + 10, y0: sy + 3, x1: sx + 10 + w, y1: sy + 17 };
    if (!labels.some((l) => overlaps(l, box))) {
      g.fillStyle = "#ff9f43";
      g.fillText(f.label, sx + 10, sy + 10);
    }
    g.restore();
    return drawn;
  }

  private labelWidth(m: MapFrame, g: CanvasRenderingContext2D, i: number): number {
    let w = this.widths.get(i);
    if (w === undefined) {
      w = Math.ceil(g.measureText(m.names[i]).width) + 6;
      this.widths.set(i, w);
    }
    return w;
  }

  private drawLabel(m: MapFrame, g: CanvasRenderingContext2D, i: number, box: Box, colour: string, plate: boolean): void {
    if (plate) {
      g.fillStyle = "rgba(12,13,16,0.9)";
      g.fillRect(box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0);
    }
    const y = 0.5 * (box.y0 + box.y1);
    g.lineWidth = 3;
    g.strokeStyle = "rgba(16,18,22,0.85)";
    g.strokeText(m.names[i], box.x0 + 3, y);
    g.fillStyle = colour;
    g.fillText(m.names[i], box.x0 + 3, y);
  }

  /** "No data here": mid grey with dark diagonals (the same look as `matlas map`). */
  private hatchPattern(g: CanvasRenderingContext2D): CanvasPattern | string {
    if (!this.hatch) {
      const c = document.createElement("canvas");
      c.width = c.height = 9;
      const h = c.getContext("2d")!;
      h.fillStyle = "#666a70";
      h.fillRect(0, 0, 9, 9);
      h.strokeStyle = "#2a2c30";
      h.lineWidth = 2;
      h.beginPath();
      for (const o of [-9, 0, 9]) {
        h.moveTo(o, 9);
        h.lineTo(o + 9, 0);
      }
      h.stroke();
      this.hatch = g.createPattern(c, "repeat");
    }
    return this.hatch ?? "#666a70";
  }

  private drawGrid(m: MapFrame, g: CanvasRenderingContext2D, width: number, height: number): void {
    const span = m.view.x1 - m.view.x0;
    const step = niceStep(span / 6);
    g.strokeStyle = "rgba(255,255,255,0.07)";
    g.fillStyle = "rgba(255,255,255,0.35)";
    g.lineWidth = 1;
    g.font = "10px system-ui, sans-serif";
    const { x0, x1, y0, y1 } = m.view;
    for (let u = Math.ceil(x0 / step) * step; u <= x1; u += step) {
      const [sx] = m.toScreen(u, 0);
      g.beginPath(); g.moveTo(sx, 0); g.lineTo(sx, height); g.stroke();
      g.fillText(fmt(u, step), sx + 3, height - 8);
    }
    for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) {
      const [, sy] = m.toScreen(0, v);
      g.beginPath(); g.moveTo(0, sy); g.lineTo(width, sy); g.stroke();
      g.fillText(fmt(v, step), 4, sy - 6);
    }
  }
}
