// Bounded load test of the preview endpoint on loopback: C concurrent clients, each a user dragging
// on the map (one request in flight; the next one `think` ms after the previous answer), for a
// fixed duration; reports errors, throughput and latency percentiles. Traffic goes only to the
// given loopback URL and stops by itself.
//
//   node bench/load_test.mjs [--url http://127.0.0.1:8080/] [--clients 50] [--seconds 30]
//                            [--size 128] [--think 100] [--slow 100] [--slow-addresses 4]
//
// --slow N adds N hostile connections beside the normal clients, from other loopback source
// addresses (127.0.0.2, 127.0.0.3, ...: other "clients" for the server's per-client limit): a
// third stay idle (connect, send nothing), a third trickle one header line every 3 s, a third
// send a request body one byte a second. Each reconnects when the server closes it, until the
// end. The report adds how often they were cut off or refused, and the server's peak memory if
// --pid is given.
//
// Exit status 1 if any normal request failed (non-200, timeout or connection error).
import net from "node:net";
import { readFileSync } from "node:fs";
import { parseArgs } from "node:util";

const { values: o } = parseArgs({
  options: {
    url: { type: "string", default: "http://127.0.0.1:8080/" },
    clients: { type: "string", default: "50" },
    seconds: { type: "string", default: "30" },
    size: { type: "string", default: "128" },
    think: { type: "string", default: "100" },
    slow: { type: "string", default: "0" },
    "slow-addresses": { type: "string", default: "4" },
    pid: { type: "string", default: "" },
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
      if (errorSamples.length < 5) errorSamples.push(String(e) + (e.cause ? ` (${e.cause.code ?? ""} ${e.cause.message ?? e.cause})` : ""));
    }
    if (think > 0) await sleep(think);
  }
}

// ---- slow clients: raw sockets, bounded by the same deadline
const slowCount = Number(o.slow), slowAddresses = Math.max(1, Number(o["slow-addresses"]));
const slowStats = { connections: 0, closedByServer: 0, refused503: 0, errors: 0 };
const sockets = new Set();
function slowClient(id) {
  return new Promise((resolve) => {
    const kind = id % 3;  // 0 idle, 1 trickling headers, 2 trickling body
    const localAddress = `127.0.0.${2 + (id % slowAddresses)}`;
    let timer = null;
    const connect = () => {
      if (performance.now() >= deadline) return resolve();
      slowStats.connections++;
      const sock = net.connect({ host: base.hostname, port: Number(base.port || 80), localAddress });
      sockets.add(sock);
      let line = 0;
      sock.on("connect", () => {
        if (kind === 1) {
          sock.write("GET /api/model HTTP/1.1\r\n");
          timer = setInterval(() => sock.write(`X-Slow-${line++}: 1\r\n`), 3000);
        } else if (kind === 2) {
          sock.write("POST /api/weights HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 1000\r\n\r\n");
          timer = setInterval(() => sock.write("["), 1000);
        }
      });
      sock.on("data", (d) => { if (d.toString().startsWith("HTTP/1.1 503")) slowStats.refused503++; });
      sock.on("error", () => { slowStats.errors++; });
      sock.on("close", () => {
        clearInterval(timer);
        sockets.delete(sock);
        if (performance.now() < deadline) slowStats.closedByServer++;
        setTimeout(connect, 200);
      });
    };
    setTimeout(connect, (id * 20) % 1000);
  });
}
function peakMemoryMb(pid) {
  try {
    const m = /VmHWM:\s+(\d+) kB/.exec(readFileSync(`/proc/${pid}/status`, "utf8"));
    return m ? Number(m[1]) / 1024 : NaN;
  } catch { return NaN; }
}
const slowDone = Promise.all(Array.from({ length: slowCount }, (_, i) => slowClient(i)));
const endSlow = setTimeout(() => { for (const s of sockets) s.destroy(); }, seconds * 1000 + 100);
if (slowCount) await sleep(1500);  // the hostile connections are in place before measuring

const t0 = performance.now();
await Promise.all(Array.from({ length: clients }, (_, i) => client(i)));
const elapsed = (performance.now() - t0) / 1000;
latencies.sort((a, b) => a - b);
const q = (p) => (latencies.length ? latencies[Math.min(latencies.length - 1, Math.floor(p * latencies.length))] : NaN);
console.log(`load test: ${clients} clients, ${seconds} s, ${size}px previews, think ${think} ms, n = ${model.count}`);
console.log(`requests ${latencies.length + errors}, errors ${errors}, throughput ${(latencies.length / elapsed).toFixed(1)} req/s`);
console.log(`latency ms: p50 ${q(0.5).toFixed(1)}  p90 ${q(0.9).toFixed(1)}  p99 ${q(0.99).toFixed(1)}  max ${q(1).toFixed(1)}`);
if (errors) console.log(`errors: ${errorSamples.join("; ")}`);
if (slowCount) {
  for (const sock of sockets) sock.destroy();
  clearTimeout(endSlow);
  await slowDone;
  console.log(`slow clients: ${slowCount} from ${slowAddresses} addresses; ${slowStats.connections} connections, ` +
              `${slowStats.closedByServer} closed by the server, ${slowStats.refused503} refused (503), ` +
              `${slowStats.errors} socket errors`);
}
if (o.pid) console.log(`server peak resident memory: ${peakMemoryMb(o.pid).toFixed(0)} MB`);
process.exit(errors ? 1 : 0);
