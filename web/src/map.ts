// LatentMap: the canvas showing one plane of the latent space: the database materials as labelled
// points, an optional background layer image, the current point, a path segment and an uploaded
// (projected) material. Pointer: click or drag to move the current point; Shift+drag, or drag
// with the middle or right button, pans the view; wheel zooms around the cursor; double-click
// resets the view. Keyboard (canvas focused): arrows move the point (Shift: 5x), Alt+arrows pan,
// +/- zoom, 0 resets the view. Labels are decluttered (labels.ts): those that would overlap are
// hidden, shown on hover, and come back as zooming in spreads the markers. Where the albedo layer
// is transparent (far from the data) a hatched grey says "no data here".
import { isolation, overlaps, placeLabels, type Box } from "./labels";

export interface ViewRect {
  x0: number;
  x1: number;
  y0: number;
  y1: number;
}

export interface MapCallbacks {
  /** The current point moved (dragging: the pointer is still down). */
  move(x: number[], dragging: boolean, eventTime: number): void;
  hover(index: number | null, clientX: number, clientY: number): void;
  viewChanged(rect: ViewRect): void;
}

export interface MapMarker {
  x: number[];
  label: string;
}

export class LatentMap {
  axes: [number, number] = [0, 1];
  point: number[];
  showLabels = true;
  path: { a: number[]; b: number[]; samples: number[][] } | null = null;
  projected: MapMarker | null = null;

  private cx = 0;
  private cy = 0;
  /** Half the view's width in latent units (its height follows the canvas' aspect). */
  private half = 1;
  private layer: { image: ImageBitmap; rect: ViewRect; hatched: boolean } | null = null;
  /** The labels drawn by the last frame (decluttered; not the hovered one), for the page and tests. */
  labelBoxes: { index: number; box: Box }[] = [];
  /** Materials whose marker is inside the canvas in the last frame. */
  visibleMaterials = 0;
  /** The hovered material's label box when it was drawn on hover only (its label is otherwise hidden). */
  hoverLabel: { index: number; box: Box } | null = null;
  /** Called after each frame (the page updates its label count). */
  onDrawn: (() => void) | null = null;
  private widths = new Map<number, number>();
  private hatch: CanvasPattern | null = null;
  private dragging = false;
  /** Panning: the latent point held under the pointer. */
  private panAnchor: [number, number] | null = null;
  private hovered: number | null = null;
  private frame = 0;

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly latent: number[][],
    private readonly names: string[],
    private readonly colors: [number, number, number][],
    private readonly domain: { min: number[]; max: number[] },
    private readonly bounds: { min: number[]; max: number[] },
    private readonly cb: MapCallbacks,
  ) {
    this.point = bounds.min.map((lo, i) => 0.5 * (lo + bounds.max[i]));
    this.resetView(false);
    new ResizeObserver(() => this.redraw()).observe(canvas);
    canvas.addEventListener("pointerdown", (e) => this.onPointerDown(e));
    canvas.addEventListener("pointermove", (e) => this.onPointerMove(e));
    canvas.addEventListener("pointerup", (e) => this.onPointerUp(e));
    canvas.addEventListener("pointercancel", (e) => this.onPointerUp(e));
    canvas.addEventListener("pointerleave", () => this.setHover(null, 0, 0));
    canvas.addEventListener("wheel", (e) => this.onWheel(e), { passive: false });
    canvas.addEventListener("dblclick", () => this.resetView(true));
    canvas.addEventListener("contextmenu", (e) => e.preventDefault());
    canvas.addEventListener("keydown", (e) => this.onKey(e));
  }

  get view(): ViewRect {
    const hy = this.half * this.aspect();
    return { x0: this.cx - this.half, x1: this.cx + this.half, y0: this.cy - hy, y1: this.cy + hy };
  }

  /** Canvas height over width. */
  private aspect(): number {
    const r = this.canvas.getBoundingClientRect();
    return r.width > 0 && r.height > 0 ? r.height / r.width : 1;
  }

  /**
   * Fits the view to the data of the current plane: the latent points' bounding box plus 10 % of
   * its longer side on every side. The canvas takes the box's aspect (from 1:1 to 3:2, never
   * taller than wide) so that a wide cloud of points is not framed by empty bands.
   */
  resetView(notify = true, core = false): void {
    const [a, b] = this.axes;
    let lo = [this.bounds.min[a], this.bounds.min[b]];
    let hi = [this.bounds.max[a], this.bounds.max[b]];
    if (core) [lo, hi] = coreBox(this.latent.map((p) => [p[a], p[b]]));
    const pad = MARGIN * Math.max(hi[0] - lo[0], hi[1] - lo[1], 1e-6);
    const du = hi[0] - lo[0] + 2 * pad, dv = hi[1] - lo[1] + 2 * pad;
    this.canvas.style.aspectRatio = String(clamp(du / dv, 1, 1.5));
    this.cx = 0.5 * (lo[0] + hi[0]);
    this.cy = 0.5 * (lo[1] + hi[1]);
    this.half = 0.5 * Math.max(du, dv / this.aspect());
    this.redraw();
    if (notify) this.cb.viewChanged(this.view);
  }

  setAxes(axes: [number, number]): void {
    this.axes = axes;
    this.layer = null;
    this.resetView(true);
  }

  /** The background layer over `rect`; `hatched`: draw "no data here" where the image is transparent. */
  setLayer(image: ImageBitmap | null, rect: ViewRect, hatched = false): void {
    this.layer = image ? { image, rect, hatched } : null;
    this.redraw();
  }

  /** Moves the current point programmatically (no callback). */
  setPoint(x: number[]): void {
    this.point = x.slice();
    this.redraw();
  }

  /** Screen position (CSS pixels relative to the canvas) of latent coordinates (u, v). */
  toScreen(u: number, v: number): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    const s = r.width / (2 * this.half);
    return [(u - (this.cx - this.half)) * s, r.height / 2 - (v - this.cy) * s];
  }

  toLatent(px: number, py: number): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    const s = (2 * this.half) / r.width;
    return [this.cx - this.half + px * s, this.cy + (r.height / 2 - py) * s];
  }

  /** Page coordinates of material i's point (for tests and tooltips). */
  materialClientPosition(i: number): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    const [sx, sy] = this.toScreen(this.latent[i][this.axes[0]], this.latent[i][this.axes[1]]);
    return [r.left + sx, r.top + sy];
  }

  redraw(): void {
    if (this.frame) return;
    this.frame = requestAnimationFrame(() => {
      this.frame = 0;
      this.draw();
    });
  }

  private pointAt(e: PointerEvent): number[] {
    const r = this.canvas.getBoundingClientRect();
    const [u, v] = this.toLatent(e.clientX - r.left, e.clientY - r.top);
    const x = this.point.slice();
    const [a, b] = this.axes;
    x[a] = clamp(u, this.domain.min[a], this.domain.max[a]);
    x[b] = clamp(v, this.domain.min[b], this.domain.max[b]);
    return x;
  }

  private onPointerDown(e: PointerEvent): void {
    const pan = e.button === 1 || e.button === 2 || (e.button === 0 && e.shiftKey);
    if (pan) {
      e.preventDefault();
      this.canvas.focus();
      this.canvas.setPointerCapture(e.pointerId);
      const r = this.canvas.getBoundingClientRect();
      this.panAnchor = this.toLatent(e.clientX - r.left, e.clientY - r.top);
      this.canvas.style.cursor = "grabbing";
      return;
    }
    if (e.button !== 0) return;
    this.canvas.focus();
    this.canvas.setPointerCapture(e.pointerId);
    this.dragging = true;
    this.point = this.pointAt(e);
    this.redraw();
    this.cb.move(this.point, true, e.timeStamp);
  }

  private onPointerMove(e: PointerEvent): void {
    if (this.panAnchor) {
      // Keep the anchored latent point under the pointer.
      const r = this.canvas.getBoundingClientRect();
      const [u, v] = this.toLatent(e.clientX - r.left, e.clientY - r.top);
      this.pan(this.panAnchor[0] - u, this.panAnchor[1] - v);
      return;
    }
    if (this.dragging) {
      this.point = this.pointAt(e);
      this.redraw();
      this.cb.move(this.point, true, e.timeStamp);
      return;
    }
    const r = this.canvas.getBoundingClientRect();
    const px = e.clientX - r.left, py = e.clientY - r.top;
    let best: number | null = null;
    let bestD = 10 * 10;
    this.latent.forEach((p, i) => {
      const [sx, sy] = this.toScreen(p[this.axes[0]], p[this.axes[1]]);
      const d = (sx - px) ** 2 + (sy - py) ** 2;
      if (d < bestD) {
        bestD = d;
        best = i;
      }
    });
    this.setHover(best, e.clientX, e.clientY);
  }

  private onPointerUp(e: PointerEvent): void {
    if (this.panAnchor) {
      this.panAnchor = null;
      this.canvas.style.cursor = "";
      if (this.canvas.hasPointerCapture(e.pointerId)) this.canvas.releasePointerCapture(e.pointerId);
      return;
    }
    if (!this.dragging) return;
    this.dragging = false;
    if (this.canvas.hasPointerCapture(e.pointerId)) this.canvas.releasePointerCapture(e.pointerId);
    this.cb.move(this.point, false, e.timeStamp);
  }

  private setHover(index: number | null, clientX: number, clientY: number): void {
    if (index !== this.hovered) {
      this.hovered = index;
      this.redraw();
    }
    this.cb.hover(index, clientX, clientY);
  }

  private onWheel(e: WheelEvent): void {
    e.preventDefault();
    const r = this.canvas.getBoundingClientRect();
    const [u, v] = this.toLatent(e.clientX - r.left, e.clientY - r.top);
    this.zoom(Math.exp(e.deltaY * 0.0015), u, v);
  }

  private zoom(factor: number, u: number, v: number): void {
    const half = clamp(this.half * factor, 1e-4, 1e4);
    const f = half / this.half;
    this.cx = u + (this.cx - u) * f;
    this.cy = v + (this.cy - v) * f;
    this.half = half;
    this.redraw();
    this.cb.viewChanged(this.view);
  }

  /** Moves the view by (du, dv) in latent units. */
  pan(du: number, dv: number): void {
    this.cx += du;
    this.cy += dv;
    this.redraw();
    this.cb.viewChanged(this.view);
  }

  private onKey(e: KeyboardEvent): void {
    if (e.altKey && e.key.startsWith("Arrow")) {
      e.preventDefault();
      const d = 0.1 * 2 * this.half;
      const du = e.key === "ArrowLeft" ? -d : e.key === "ArrowRight" ? d : 0;
      const dv = e.key === "ArrowDown" ? -d : e.key === "ArrowUp" ? d : 0;
      this.pan(du, dv);
      return;
    }
    const step = (e.shiftKey ? 0.05 : 0.01) * 2 * this.half;
    const [a, b] = this.axes;
    const x = this.point.slice();
    switch (e.key) {
      case "ArrowLeft": x[a] -= step; break;
      case "ArrowRight": x[a] += step; break;
      case "ArrowUp": x[b] += step; break;
      case "ArrowDown": x[b] -= step; break;
      case "+": case "=": this.zoom(1 / 1.25, this.point[a], this.point[b]); return;
      case "-": this.zoom(1.25, this.point[a], this.point[b]); return;
      case "0": this.resetView(true); return;
      default: return;
    }
    e.preventDefault();
    x[a] = clamp(x[a], this.domain.min[a], this.domain.max[a]);
    x[b] = clamp(x[b], this.domain.min[b], this.domain.max[b]);
    this.point = x;
    this.redraw();
    this.cb.move(x, false, e.timeStamp);
  }

  private draw(): void {
    const c = this.canvas;
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
    const [a, b] = this.axes;

    if (this.layer) {
      const { x0, x1, y0, y1 } = this.layer.rect;
      const [sx0, sy0] = this.toScreen(x0, y1);
      const [sx1, sy1] = this.toScreen(x1, y0);
      g.imageSmoothingEnabled = true;
      if (this.layer.hatched) {
        g.fillStyle = this.hatchPattern(g);
        g.fillRect(sx0, sy0, sx1 - sx0, sy1 - sy0);
      }
      g.globalAlpha = this.layer.hatched ? 1 : 0.9;  // the hatch must not show through the data
      g.drawImage(this.layer.image, sx0, sy0, sx1 - sx0, sy1 - sy0);
      g.globalAlpha = 1;
    }
    this.drawGrid(g, r.width, r.height);

    if (this.path) {
      const [ax, ay] = this.toScreen(this.path.a[a], this.path.a[b]);
      const [bx, by] = this.toScreen(this.path.b[a], this.path.b[b]);
      g.strokeStyle = "#f5c04a";
      g.lineWidth = 2;
      g.setLineDash([6, 4]);
      g.beginPath();
      g.moveTo(ax, ay);
      g.lineTo(bx, by);
      g.stroke();
      g.setLineDash([]);
      g.fillStyle = "#f5c04a";
      for (const s of this.path.samples) {
        const [sx, sy] = this.toScreen(s[a], s[b]);
        g.fillRect(sx - 2, sy - 2, 4, 4);
      }
    }

    g.font = "11px system-ui, sans-serif";
    g.textBaseline = "middle";
    // Markers inside the canvas, and their decluttered labels.
    const visible: number[] = [], xs: number[] = [], ys: number[] = [];
    this.latent.forEach((p, i) => {
      const [sx, sy] = this.toScreen(p[a], p[b]);
      if (sx < -8 || sy < -8 || sx > r.width + 8 || sy > r.height + 8) return;
      visible.push(i);
      xs.push(sx);
      ys.push(sy);
    });
    this.visibleMaterials = visible.length;
    const labelHeight = 15;
    let boxes: (Box | null)[] = visible.map(() => null);
    if (this.showLabels) {
      const priority = isolation(xs, ys);
      boxes = placeLabels(
        visible.map((i, k) => ({ x: xs[k], y: ys[k], width: this.labelWidth(g, i), height: labelHeight, priority: priority[k] })),
        r.width, r.height, 7);
    }
    this.labelBoxes = [];
    this.hoverLabel = null;
    visible.forEach((i, k) => {
      const [sx, sy] = [xs[k], ys[k]];
      const [cr, cg, cb] = this.colors[i] ?? [200, 200, 200];
      g.beginPath();
      g.arc(sx, sy, i === this.hovered ? 7 : 5, 0, 2 * Math.PI);
      g.fillStyle = `rgb(${cr},${cg},${cb})`;
      g.fill();
      g.lineWidth = i === this.hovered ? 2 : 1;
      g.strokeStyle = i === this.hovered ? "#ffffff" : "rgba(255,255,255,0.55)";
      g.stroke();
    });
    visible.forEach((i, k) => {
      const box = boxes[k];
      if (!box) return;
      this.labelBoxes.push({ index: i, box });
      this.drawLabel(g, i, box, i === this.hovered ? "#ffffff" : "#c9ced8", false);
    });
    if (this.hovered !== null && !this.labelBoxes.some((l) => l.index === this.hovered)) {
      // A hidden label on hover: on top of the others, on a dark plate.
      const i = this.hovered;
      const [sx, sy] = this.toScreen(this.latent[i][a], this.latent[i][b]);
      const w = this.labelWidth(g, i);
      const x0 = sx + 10 + w > r.width ? sx - 10 - w : sx + 10;
      const box = { x0, y0: sy - labelHeight / 2, x1: x0 + w, y1: sy + labelHeight / 2 };
      this.hoverLabel = { index: i, box };
      this.drawLabel(g, i, box, "#ffffff", true);
    }

    if (this.projected) {
      const [sx, sy] = this.toScreen(this.projected.x[a], this.projected.x[b]);
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
      const w = g.measureText(this.projected.label).width;
      const box = { x0: sx + 10, y0: sy - 17, x1: sx + 10 + w, y1: sy - 3 };
      if (!this.labelBoxes.some((l) => overlaps(l.box, box))) {
        g.fillStyle = "#58d68d";
        g.fillText(this.projected.label, sx + 10, sy - 10);
      }
    }

    const [px, py] = this.toScreen(this.point[a], this.point[b]);
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
    this.onDrawn?.();
  }

  private labelWidth(g: CanvasRenderingContext2D, i: number): number {
    let w = this.widths.get(i);
    if (w === undefined) {
      w = Math.ceil(g.measureText(this.names[i]).width) + 6;
      this.widths.set(i, w);
    }
    return w;
  }

  private drawLabel(g: CanvasRenderingContext2D, i: number, box: Box, colour: string, plate: boolean): void {
    if (plate) {
      g.fillStyle = "rgba(12,13,16,0.9)";
      g.fillRect(box.x0, box.y0, box.x1 - box.x0, box.y1 - box.y0);
    }
    const y = 0.5 * (box.y0 + box.y1);
    g.lineWidth = 3;
    g.strokeStyle = "rgba(16,18,22,0.85)";
    g.strokeText(this.names[i], box.x0 + 3, y);
    g.fillStyle = colour;
    g.fillText(this.names[i], box.x0 + 3, y);
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

  private drawGrid(g: CanvasRenderingContext2D, width: number, height: number): void {
    const span = 2 * this.half;
    const step = niceStep(span / 6);
    g.strokeStyle = "rgba(255,255,255,0.07)";
    g.fillStyle = "rgba(255,255,255,0.35)";
    g.lineWidth = 1;
    g.font = "10px system-ui, sans-serif";
    const { x0, x1, y0, y1 } = this.view;
    for (let u = Math.ceil(x0 / step) * step; u <= x1; u += step) {
      const [sx] = this.toScreen(u, 0);
      g.beginPath(); g.moveTo(sx, 0); g.lineTo(sx, height); g.stroke();
      g.fillText(fmt(u, step), sx + 3, height - 8);
    }
    for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) {
      const [, sy] = this.toScreen(0, v);
      g.beginPath(); g.moveTo(0, sy); g.lineTo(width, sy); g.stroke();
      g.fillText(fmt(v, step), 4, sy - 6);
    }
  }
}

/**
 * The box of the materials within 4 median distances of the per-axis median point (at least half
 * of them), as `matlas map --frame core`: the crowd when a few outliers stretch the data's box.
 */
export function coreBox(points: number[][]): [number[], number[]] {
  const median = (v: number[]) => v.slice().sort((x, y) => x - y)[v.length >> 1];
  const mu = median(points.map((p) => p[0])), mv = median(points.map((p) => p[1]));
  const d = points.map((p) => Math.hypot(p[0] - mu, p[1] - mv));
  const limit = 4 * median(d);
  const lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
  points.forEach((p, i) => {
    if (d[i] > limit) return;
    for (const k of [0, 1]) {
      lo[k] = Math.min(lo[k], p[k]);
      hi[k] = Math.max(hi[k], p[k]);
    }
  });
  return [lo, hi];
}

/** Margin of the fitted view on every side, as a fraction of the data box's longer side (as `matlas map`). */
const MARGIN = 0.1;

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

function niceStep(raw: number): number {
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

/** A grid value with as many decimals as the grid's step needs (ticks stay distinct when zoomed in). */
function fmt(v: number, step: number): string {
  if (Math.abs(v) < 1e-9 * step) return "0";
  const decimals = Math.max(0, Math.min(10, -Math.floor(Math.log10(step) + 1e-9)));
  return v.toFixed(decimals);
}
