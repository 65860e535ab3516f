// Geometry helpers of the latent map: the crowd's box, the fitted view's margin, grid steps and
// tick labels.

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
export const MARGIN = 0.1;

export function clamp(v: number, lo: number, hi: number): number {
  return Math.min(hi, Math.max(lo, v));
}

export function niceStep(raw: number): number {
  const p = Math.pow(10, Math.floor(Math.log10(raw)));
  const m = raw / p;
  return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

/** A grid value with as many decimals as the grid's step needs (ticks stay distinct when zoomed in). */
export function fmt(v: number, step: number): string {
  if (Math.abs(v) < 1e-9 * step) return "0";
  const decimals = Math.max(0, Math.min(10, -Math.floor(Math.log10(step) + 1e-9)));
  return v.toFixed(decimals);
}
