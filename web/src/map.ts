// LatentMap: the canvas showing one plane of the latent space: the database materials as labelled
// points, an optional background layer image, the current point, a path segment, an uploaded
// (projected) material and fitted samples with their uncertainty ellipse. Pointer: click or drag to move the current point; Shift+drag, or drag
// with the middle or right button, pans the view; wheel zooms around the cursor; double-click
// resets the view. Keyboard (canvas focused): arrows move the point (Shift: 5x), Alt+arrows pan,
// +/- zoom, 0 resets the view. Labels are decluttered (labels.ts): those that would overlap are
// hidden, shown on hover, and come back as zooming in spreads the markers. Where the albedo layer
// is transparent (far from the data) a hatched grey says "no data here".
import type { Box } from "./labels";
import {
  MapPainter, type DrawnEllipse, type FitMarker, type MapFrame, type MapLayerImage, type MapMarker, type MapPath, type ViewRect,
} from "./map-draw";
import { clamp, coreBox, MARGIN } from "./map-geometry";

export type { FitMarker, MapMarker, ViewRect } from "./map-draw";

export interface MapCallbacks {
  /** The current point moved (dragging: the pointer is still down). */
  move(x: number[], dragging: boolean, eventTime: number): void;
  hover(index: number | null, clientX: number, clientY: number): void;
  viewChanged(rect: ViewRect): void;
}

export class LatentMap implements MapFrame {
  axes: [number, number] = [0, 1];
  point: number[];
  showLabels = true;
  path: MapPath | null = null;
  projected: MapMarker | null = null;
  /** A fitted sample file (fit-samples.ts): its point and covariance. */
  fitted: FitMarker | null = null;
  /** The fit's ellipse as the last frame drew it (for the page and tests). */
  fitEllipse: DrawnEllipse | null = null;

  private cx = 0;
  private cy = 0;
  /** Half the view's width in latent units (its height follows the canvas' aspect). */
  private half = 1;
  /** The background layer (read by the painter). */
  layer: MapLayerImage | null = null;
  /** The labels drawn by the last frame (decluttered; not the hovered one), for the page and tests. */
  labelBoxes: { index: number; box: Box }[] = [];
  /** Materials whose marker is inside the canvas in the last frame. */
  visibleMaterials = 0;
  /** The hovered material's label box when it was drawn on hover only (its label is otherwise hidden). */
  hoverLabel: { index: number; box: Box } | null = null;
  /** Called after each frame (the page updates its label count). */
  onDrawn: (() => void) | null = null;
  /** Called after every change of the view (pan, zoom, fit), besides the page's layer refresh. */
  readonly viewListeners: (() => void)[] = [];
  /** Each material's marker opacity in the last frame (q > 2: its distance from the slice). */
  markerAlpha: number[] = [];
  private readonly painter = new MapPainter();
  private dragging = false;
  /** Panning: the latent point held under the pointer. */
  private panAnchor: [number, number] | null = null;
  /** The hovered material (read by the painter). */
  hovered: number | null = null;
  private frame = 0;

  constructor(
    readonly canvas: HTMLCanvasElement,
    readonly latent: number[][],
    readonly names: string[],
    readonly colors: [number, number, number][],
    private readonly domain: { min: number[]; max: number[] },
    readonly bounds: { min: number[]; max: number[] },
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

  /** The view's centre and half width in latent units (for the address bar). */
  viewState(): { cx: number; cy: number; half: number } {
    return { cx: this.cx, cy: this.cy, half: this.half };
  }

  /** Restores a view saved by viewState(). */
  setViewState(v: { cx: number; cy: number; half: number }): void {
    this.cx = v.cx;
    this.cy = v.cy;
    this.half = clamp(v.half, 1e-4, 1e4);
    this.redraw();
    this.notifyView();
  }

  private notifyView(): void {
    this.cb.viewChanged(this.view);
    for (const f of this.viewListeners) f();
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
    if (notify) this.notifyView();
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
      const drawn = this.painter.draw(this);
      this.labelBoxes = drawn.labelBoxes;
      this.visibleMaterials = drawn.visibleMaterials;
      this.hoverLabel = drawn.hoverLabel;
      this.markerAlpha = drawn.alpha;
      this.fitEllipse = drawn.fitEllipse;
      this.onDrawn?.();
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
    this.notifyView();
  }

  /** Moves the view by (du, dv) in latent units. */
  pan(du: number, dv: number): void {
    this.cx += du;
    this.cy += dv;
    this.redraw();
    this.notifyView();
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
}
