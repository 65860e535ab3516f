// The theta_h x theta_d slice drawn with its scales: the server's image (POST /api/slice: column i
// is theta_h bin i, whose angle is 90 (i / N)^2 degrees as in MERL tables; row j is theta_d bin j,
// linear; values log(1 + f / 0.01) normalised by the slice's maximum, the same curve per channel),
// degree ticks on both axes, and a colour bar whose ticks are BRDF values (sr^-1).
const KS = 0.01;

/** Colour-bar ticks: 0 and the decades 0.01 ... up to vmax (every other decade if more than n). */
export function logTicks(vmax: number, n = 6): number[] {
  const decades: number[] = [];
  for (let e = -2; e <= 5; e++) if (10 ** e <= vmax * 1.0001) decades.push(10 ** e);
  const step = decades.length + 1 > n ? 2 : 1;
  return [0, ...decades.filter((_, i) => (decades.length - 1 - i) % step === 0)];
}

/** Where value f sits on the colour bar (0 bottom, 1 top). */
export const scalePosition = (f: number, vmax: number) => Math.log1p(Math.max(f, 0) / KS) / Math.log1p(Math.max(vmax, 1e-9) / KS);

const fmtValue = (v: number) => (v === 0 ? "0" : v >= 1 ? String(Math.round(v)) : v.toPrecision(1));

export class SlicePlot {
  /** What the last frame drew (the tests read it): the colour bar's values and the tick angles. */
  drawn: { max: number; valueTicks: number[]; thetaH: number[]; thetaD: number[] } | null = null;
  private image: HTMLImageElement | null = null;
  private max = 0;

  constructor(private readonly canvas: HTMLCanvasElement) {
    new ResizeObserver(() => this.draw()).observe(canvas);
  }

  show(image: HTMLImageElement, max: number): void {
    this.image = image;
    this.max = max;
    this.draw();
  }

  draw(): void {
    const c = this.canvas, img = this.image;
    const dpr = window.devicePixelRatio || 1;
    const r = c.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) return;
    c.width = Math.round(r.width * dpr);
    c.height = Math.round(r.height * dpr);
    const g = c.getContext("2d")!;
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    g.clearRect(0, 0, r.width, r.height);
    if (!img || !img.naturalWidth) return;
    // Layout: θd ticks left, the square image, a gap, the colour bar with its value ticks right;
    // θh ticks below.
    const left = 30, bottom = 30, top = 4, barW = 12, barLabels = 38;
    const side = Math.max(40, Math.min(r.height - bottom - top, r.width - left - 12 - barW - barLabels));
    const x0 = left + Math.max(0, (r.width - left - side - 12 - barW - barLabels) / 2), y0 = top;
    g.imageSmoothingEnabled = false;
    g.drawImage(img, x0, y0, side, side);
    g.strokeStyle = "#3a3f4a";
    g.strokeRect(x0 + 0.5, y0 + 0.5, side - 1, side - 1);
    g.fillStyle = "#9aa3b2";
    g.strokeStyle = "#9aa3b2";
    g.font = "10px system-ui, sans-serif";
    // θh: bin i of N covers [90 (i/N)^2, 90 ((i+1)/N)^2]: the angle a at x = sqrt(a / 90).
    const thetaH = [0, 5, 20, 45, 90];
    g.textAlign = "center";
    g.textBaseline = "top";
    for (const a of thetaH) {
      const x = x0 + side * Math.sqrt(a / 90);
      g.beginPath(); g.moveTo(x, y0 + side); g.lineTo(x, y0 + side + 4); g.stroke();
      g.fillText(`${a}°`, Math.min(Math.max(x, x0 + 8), x0 + side - 6), y0 + side + 5);
    }
    g.fillText("θh (half vector)", x0 + side / 2, y0 + side + 17);
    const thetaD = [0, 30, 60, 90];
    g.textAlign = "right";
    g.textBaseline = "middle";
    for (const a of thetaD) {
      const y = y0 + side * (a / 90);
      g.beginPath(); g.moveTo(x0 - 4, y); g.lineTo(x0, y); g.stroke();
      g.fillText(`${a}°`, x0 - 5, Math.min(Math.max(y, y0 + 5), y0 + side - 5));
    }
    g.save();
    g.translate(9, y0 + side / 2);
    g.rotate(-Math.PI / 2);
    g.textAlign = "center";
    g.fillText("θd ↓", 0, 0);
    g.restore();
    // The colour bar: the same log curve as the image (grey: every channel uses it), sRGB encoded.
    const bx = x0 + side + 12;
    const grad = g.createLinearGradient(0, y0 + side, 0, y0);
    for (let k = 0; k <= 16; k++) {
      const t = k / 16, s = t <= 0.0031308 ? 12.92 * t : 1.055 * t ** (1 / 2.4) - 0.055;
      const v = Math.round(255 * s);
      grad.addColorStop(t, `rgb(${v},${v},${v})`);
    }
    g.fillStyle = grad;
    g.fillRect(bx, y0, barW, side);
    g.strokeStyle = "#3a3f4a";
    g.strokeRect(bx + 0.5, y0 + 0.5, barW - 1, side - 1);
    const ticks = logTicks(this.max);
    g.fillStyle = "#9aa3b2";
    g.strokeStyle = "#9aa3b2";
    g.textAlign = "left";
    let lastY = Infinity;
    const shown: number[] = [];
    for (const v of ticks) {
      const y = y0 + side * (1 - scalePosition(v, this.max));
      if (lastY - y < 12) continue;  // too close to the one below (0.01 just above 0)
      lastY = y;
      g.beginPath(); g.moveTo(bx + barW, y); g.lineTo(bx + barW + 3, y); g.stroke();
      g.fillText(fmtValue(v), bx + barW + 5, Math.min(Math.max(y, y0 + 5), y0 + side - 5));
      shown.push(v);
    }
    g.fillText("sr⁻¹", bx + barW + 5, y0 + side + 10);
    this.drawn = { max: this.max, valueTicks: shown, thetaH, thetaD };
  }
}
