// LatentMap: the canvas showing one plane of the latent space: the database materials as labelled
// points, an optional background layer image, the current point, a path segment and an uploaded
// (projected) material. Pointer: click or drag to move the current point; Shift+drag, or drag
// with the middle or right button, pans the view; wheel zooms around the cursor; double-click
// resets the view. Keyboard (canvas focused): arrows move the point (Shift: 5x), Alt+arrows pan,
// +/- zoom, 0 resets the view.

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
  private half = 1;
  private layer: { image: ImageBitmap; rect: ViewRect } | null = null;
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
    return { x0: this.cx - this.half, x1: this.cx + this.half, y0: this.cy - this.half, y1: this.cy + this.half };
  }

  /** Fits the view to the data of the current plane, with a margin. */
  resetView(notify = true): void {
    const [a, b] = this.axes;
    const lo = [this.bounds.min[a], this.bounds.min[b]];
    const hi = [this.bounds.max[a], this.bounds.max[b]];
    this.cx = 0.5 * (lo[0] + hi[0]);
    this.cy = 0.5 * (lo[1] + hi[1]);
    this.half = 0.5 * Math.max(hi[0] - lo[0], hi[1] - lo[1], 1e-6) * 1.18;
    this.redraw();
    if (notify) this.cb.viewChanged(this.view);
  }

  setAxes(axes: [number, number]): void {
    this.axes = axes;
    this.layer = null;
    this.resetView(true);
  }

  setLayer(image: ImageBitmap | null, rect: ViewRect): void {
    this.layer = image ? { image, rect } : null;
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
    return [(u - (this.cx - this.half)) * s, (this.cy + this.half - v) * s];
  }

  toLatent(px: number, py: number): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    const s = (2 * this.half) / r.width;
    return [this.cx - this.half + px * s, this.cy + this.half - py * s];
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
      g.globalAlpha = 0.9;
      g.drawImage(this.layer.image, sx0, sy0, sx1 - sx0, sy1 - sy0);
      g.globalAlpha = 1;
    }
    this.drawGrid(g, r.width);

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
    this.latent.forEach((p, i) => {
      const [sx, sy] = this.toScreen(p[a], p[b]);
      const [cr, cg, cb] = this.colors[i] ?? [200, 200, 200];
      g.beginPath();
      g.arc(sx, sy, i === this.hovered ? 7 : 5, 0, 2 * Math.PI);
      g.fillStyle = `rgb(${cr},${cg},${cb})`;
      g.fill();
      g.lineWidth = i === this.hovered ? 2 : 1;
      g.strokeStyle = i === this.hovered ? "#ffffff" : "rgba(255,255,255,0.55)";
      g.stroke();
      if (this.showLabels || i === this.hovered) {
        const label = this.names[i];
        g.lineWidth = 3;
        g.strokeStyle = "rgba(16,18,22,0.85)";
        g.strokeText(label, sx + 8, sy);
        g.fillStyle = i === this.hovered ? "#ffffff" : "#c9ced8";
        g.fillText(label, sx + 8, sy);
      }
    });

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
      g.fillStyle = "#58d68d";
      g.fillText(this.projected.label, sx + 10, sy - 10);
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
  }

  private drawGrid(g: CanvasRenderingContext2D, size: number): void {
    const span = 2 * this.half;
    const step = niceStep(span / 6);
    g.strokeStyle = "rgba(255,255,255,0.07)";
    g.fillStyle = "rgba(255,255,255,0.35)";
    g.lineWidth = 1;
    g.font = "10px system-ui, sans-serif";
    const { x0, x1, y0, y1 } = this.view;
    for (let u = Math.ceil(x0 / step) * step; u <= x1; u += step) {
      const [sx] = this.toScreen(u, 0);
      g.beginPath(); g.moveTo(sx, 0); g.lineTo(sx, size); g.stroke();
      g.fillText(fmt(u), sx + 3, size - 8);
    }
    for (let v = Math.ceil(y0 / step) * step; v <= y1; v += step) {
      const [, sy] = this.toScreen(0, v);
      g.beginPath(); g.moveTo(0, sy); g.lineTo(size, sy); g.stroke();
      g.fillText(fmt(v), 4, sy - 6);
    }
  }
}

function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

function niceStep(raw: number): number {
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

function fmt(v: number): string {
  return Math.abs(v) < 1e-9 ? "0" : Number(v.toPrecision(3)).toString();
}
