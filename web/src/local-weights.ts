// The model's interpolation weights computed in the page, from GET /api/interpolation: the same
// arithmetic as the server's Model::weights (src/gp/posterior.cpp, src/gp/convex_weights.cpp), in
// double precision, so that the real-time viewer follows the pointer without a round trip.
//
//   GP:     w = K^-1 k(x), K = L L^T (L from the server), k_i = exp(-|x - x_i|^2 / l^2) + delta phi_i
//   convex: c = argmin_{c >= 0, sum c = 1} (c - g)^T A (c - g),  g = w + (1 - sum w) / n,
//           by the primal active-set method of the server (Nocedal & Wright, Algorithm 16.3).
//
// A point costs about n^2 multiply-adds (two triangular solves) and, in the convex mode, a few
// active-set steps of small dense solves: 0.64 ms per point for the 83 realistic materials in node
// (bench/local_weights.mjs).
import type { InterpolationData } from "./api";

/** Cholesky factorisation of a symmetric positive definite m x m matrix (row-major), in place: the lower factor. */
function choleskyInPlace(a: Float64Array, m: number): void {
  for (let j = 0; j < m; ++j) {
    let d = a[j * m + j];
    for (let k = 0; k < j; ++k) d -= a[j * m + k] * a[j * m + k];
    if (!(d > 0)) throw new Error("local weights: the active set's metric is not positive definite");
    const ljj = Math.sqrt(d);
    a[j * m + j] = ljj;
    for (let i = j + 1; i < m; ++i) {
      let s = a[i * m + j];
      for (let k = 0; k < j; ++k) s -= a[i * m + k] * a[j * m + k];
      a[i * m + j] = s / ljj;
    }
  }
}

/** Solves L L^T y = b for the lower factor L (m x m, row-major). */
function choleskySolve(L: ArrayLike<number>, m: number, b: Float64Array): Float64Array {
  const y = Float64Array.from(b);
  for (let i = 0; i < m; ++i) {  // L z = b
    let s = y[i];
    for (let k = 0; k < i; ++k) s -= L[i * m + k] * y[k];
    y[i] = s / L[i * m + i];
  }
  for (let i = m - 1; i >= 0; --i) {  // L^T y = z
    let s = y[i];
    for (let k = i + 1; k < m; ++k) s -= L[k * m + i] * y[k];
    y[i] = s / L[i * m + i];
  }
  return y;
}

export class LocalWeights {
  readonly n: number;
  readonly q: number;
  private readonly X: Float64Array;
  private readonly L: Float64Array;
  private readonly A: Float64Array;

  constructor(readonly data: InterpolationData) {
    const n = data.latent.length;
    this.n = n;
    this.q = n ? data.latent[0].length : 0;
    if (!n || data.taper_radius.length !== n || data.cholesky.length !== n * n || data.metric.length !== n * n)
      throw new Error(`interpolation data: inconsistent sizes for ${n} materials`);
    this.X = Float64Array.from(data.latent.flat());
    this.L = Float64Array.from(data.cholesky);
    this.A = Float64Array.from(data.metric);
  }

  /** The weights of the active mode at x (length n): what POST /api/weights answers. */
  weights(x: number[]): Float64Array {
    const w = this.gp(x);
    return this.data.mode === "convex" ? this.convex(w) : w;
  }

  /** The GP weights K^-1 k(x) of the centred data. */
  gp(x: number[]): Float64Array {
    const { n, q, X } = this;
    if (x.length !== q) throw new Error(`latent point has ${x.length} coordinates, the model has q = ${q}`);
    const { lengthscale: l, nugget, taper_radius: radius } = this.data;
    const k = new Float64Array(n);
    for (let i = 0; i < n; ++i) {
      let d2 = 0;
      for (let d = 0; d < q; ++d) d2 += (X[i * q + d] - x[d]) ** 2;
      k[i] = Math.exp(-d2 / (l * l));
      if (d2 === 0) k[i] += nugget;
      else if (d2 < radius[i] * radius[i]) {
        const t = Math.sqrt(d2) / radius[i];
        k[i] += nugget * (1 - t * t) * (1 - t * t);
      }
    }
    return choleskySolve(this.L, n, k);
  }

  /** The convex weights of GP weights w: g = w + (1 - sum w) / n projected onto the simplex in the metric A. */
  convex(w: Float64Array): Float64Array {
    const { n, A } = this;
    let sum = 0;
    for (const v of w) sum += v;
    const g = w.map((v) => v + (1 - sum) / n);
    let total = 0, min = Infinity;
    for (const v of g) (total += v), (min = Math.min(min, v));
    if (min >= 0) return g.map((v) => v / total);  // already convex: the GP's own answer

    // Feasible start: g clipped at 0 and renormalised.
    const c = g.map((v) => Math.max(v, 0));
    let cs = 0;
    for (const v of c) cs += v;
    for (let i = 0; i < n; ++i) c[i] /= cs;
    const free = Array.from(c, (v) => v > 0);
    const b = new Float64Array(n);
    let bmax = 0;
    for (let r = 0; r < n; ++r) {
      let s = 0;
      for (let j = 0; j < n; ++j) s += A[r * n + j] * g[j];
      b[r] = s;
      bmax = Math.max(bmax, Math.abs(s));
    }
    const tolerance = 1e-11 * (1 + bmax);
    const maxIterations = 10 * n + 10;
    for (let iteration = 0; iteration < maxIterations; ++iteration) {
      const idx: number[] = [];
      for (let i = 0; i < n; ++i) if (free[i]) idx.push(i);
      const m = idx.length;
      // Equality-constrained problem on the free set: A_FF c_F = b_F + nu 1, sum c_F = 1.
      const AFF = new Float64Array(m * m), bF = new Float64Array(m);
      for (let r = 0; r < m; ++r) {
        bF[r] = b[idx[r]];
        for (let s = 0; s < m; ++s) AFF[r * m + s] = A[idx[r] * n + idx[s]];
      }
      choleskyInPlace(AFF, m);
      const u = choleskySolve(AFF, m, bF);
      const v = choleskySolve(AFF, m, new Float64Array(m).fill(1));
      let us = 0, vs = 0;
      for (let r = 0; r < m; ++r) (us += u[r]), (vs += v[r]);
      const nu = (1 - us) / vs;
      const cF = u.map((ur, r) => ur + nu * v[r]);
      if (Math.min(...cF) >= 0) {
        // Optimal if every bound's multiplier (A c - b)_j - nu is >= 0; otherwise free the most negative one.
        c.fill(0);
        for (let r = 0; r < m; ++r) c[idx[r]] = cF[r];
        let worst = -1, mostNegative = -tolerance;
        for (let j = 0; j < n; ++j) {
          if (free[j]) continue;
          let s = 0;
          for (let i = 0; i < n; ++i) s += A[i * n + j] * c[i];
          const lambda = s - b[j] - nu;
          if (lambda < mostNegative) (mostNegative = lambda), (worst = j);
        }
        if (worst < 0) return normalised(c);
        free[worst] = true;
        continue;
      }
      // Step towards c_F until the first free coefficient reaches 0; that one becomes bound.
      let alpha = 1, blocking = -1;
      for (let r = 0; r < m; ++r) {
        const k = idx[r];
        if (cF[r] < 0) {
          const a = c[k] / (c[k] - cF[r]);
          if (a < alpha) (alpha = a), (blocking = k);
        }
      }
      for (let r = 0; r < m; ++r) c[idx[r]] += alpha * (cF[r] - c[idx[r]]);
      if (blocking >= 0) {
        c[blocking] = 0;
        free[blocking] = false;
      }
      for (let i = 0; i < n; ++i) c[i] = Math.max(c[i], 0);
    }
    return normalised(c);  // not reached for a positive definite metric (as on the server)
  }
}

function normalised(c: Float64Array): Float64Array {
  let s = 0;
  for (const v of c) s += v;
  return c.map((v) => v / s);
}
