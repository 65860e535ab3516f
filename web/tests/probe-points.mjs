// Latent points at which the page's weights are compared with the server's (the api-schema test
// and bench/local_weights.mjs): every material, the midpoints of consecutive materials, and
// `spread` points drawn uniformly over the model's domain by a small LCG started at `seed`.
export function probePoints(model, spread, seed) {
  const points = [...model.latent];
  for (let i = 0; i + 1 < model.count; ++i) points.push(model.latent[i].map((v, d) => 0.5 * (v + model.latent[i + 1][d])));
  let state = seed;
  const random = () => ((state = (state * 1103515245 + 12345) % 2147483648) / 2147483648);
  for (let t = 0; t < spread; ++t) points.push(model.domain.min.map((lo, d) => lo + random() * (model.domain.max[d] - lo)));
  return points;
}
