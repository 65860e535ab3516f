// Bounded load test of the preview endpoint on loopback: C concurrent clients, each a user dragging
// on the map (one request in flight; the next one `think` ms after the previous answer), for a
// fixed duration; reports errors, throughput and latency percentiles. Traffic goes only to the
// given loopback URL and stops by itself.
//
//   node bench/load_test.mjs [--url http://127.0.0.1:8080/] [--clients 50] [--seconds 30]
//                            [--size 128] [--think 100]
//
// Exit status 1 if any request failed (non-200, timeout or connection error).
import { parseArgs } from "node:util";

const { values: o } = parseArgs({
  options: {
    url: { type: "string", default: "http://127.0.0.1:8080/" },
    clients: { type: "string", default: "50" },
    seconds: { type: "string", default: "30" },
    size: { type: "string", default: "128" },
    think: { type: "string", default: "100" },
  },
});
const base = new URL(o.url);
if (!["127.0.0.1", "localhost", "[::1]"].includes(base.hostname) && !base.hostname.startsWith("127."))
  throw new Error(`load_test: only loopback targets are allowed, not ${base.hostname}`);
const clients = Number(o.clients), seconds = Number(o.seconds), size = Number(o.size), think = Number(o.think);

const model = await (await fetch(new URL("api/model", base))).json();
const lo = model.bounds.min, hi = model.bounds.max;
const latencies = [];
let errors = 0;
const errorSamples = [];
const deadline = performance.now() + seconds * 1000;
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function client(id) {
  // A random walk through the latent box, like a pointer dragging.
  let x = lo.map((l, d) => l + Math.random() * (hi[d] - l));
  await sleep((id * think) / clients);  // spread the starts
  while (performance.now() < deadline) {
    x = x.map((v, d) => Math.min(hi[d], Math.max(lo[d], v + (Math.random() - 0.5) * 0.05 * (hi[d] - lo[d]))));
    const t0 = performance.now();
    try {
      const res = await fetch(new URL("api/preview", base), {
        method: "POST", headers: { "Content-Type": "application/json" },
        body: JSON.stringify({ x, size }), signal: AbortSignal.timeout(10_000),
      });
      const body = await res.arrayBuffer();
      if (res.status !== 200 || body.byteLength < 8) throw new Error(`status ${res.status}`);
      latencies.push(performance.now() - t0);
    } catch (e) {
      errors++;
      if (errorSamples.length < 5) errorSamples.push(String(e));
    }
    if (think > 0) await sleep(think);
  }
}

const t0 = performance.now();
await Promise.all(Array.from({ length: clients }, (_, i) => client(i)));
const elapsed = (performance.now() - t0) / 1000;
latencies.sort((a, b) => a - b);
const q = (p) => (latencies.length ? latencies[Math.min(latencies.length - 1, Math.floor(p * latencies.length))] : NaN);
console.log(`load test: ${clients} clients, ${seconds} s, ${size}px previews, think ${think} ms, n = ${model.count}`);
console.log(`requests ${latencies.length + errors}, errors ${errors}, throughput ${(latencies.length / elapsed).toFixed(1)} req/s`);
console.log(`latency ms: p50 ${q(0.5).toFixed(1)}  p90 ${q(0.9).toFixed(1)}  p99 ${q(0.99).toFixed(1)}  max ${q(1).toFixed(1)}`);
if (errors) console.log(`errors: ${errorSamples.join("; ")}`);
process.exit(errors ? 1 : 0);
