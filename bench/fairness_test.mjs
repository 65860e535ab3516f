// Bounded fairness test of the heavy slot on loopback: one "flooding" client address sends many
// heavy requests at once, in a loop, while a few "polite" client addresses each send one heavy
// request at a time (then think). Every client address is another loopback address (127.0.0.2 is
// the flood, 127.0.0.3, 127.0.0.4, ... the polite ones), which the server tells apart. Reports, per
// group, the answers by status and the latency percentiles of the answered (200) requests. Traffic
// goes only to the given loopback URL and stops by itself.
//
//   node bench/fairness_test.mjs [--url http://127.0.0.1:8080/] [--seconds 30] [--flood 50]
//                                [--polite 3] [--think 200] [--kind export|reference|map]
//
// Exit status 1 if a polite request failed (non-200 other than 503, or a connection error) or a
// polite client got fewer answers than a third of what a fair share allows.
import http from "node:http";
import { parseArgs } from "node:util";

const { values: o } = parseArgs({
  options: {
    url: { type: "string", default: "http://127.0.0.1:8080/" },
    seconds: { type: "string", default: "30" },
    flood: { type: "string", default: "50" },
    polite: { type: "string", default: "3" },
    think: { type: "string", default: "200" },
    kind: { type: "string", default: "export" },
  },
});
const base = new URL(o.url);
if (!["127.0.0.1", "localhost"].includes(base.hostname) && !base.hostname.startsWith("127."))
  throw new Error(`fairness_test: only loopback targets are allowed, not ${base.hostname}`);
const seconds = Number(o.seconds), flood = Number(o.flood), polite = Number(o.polite), think = Number(o.think);

const model = await (await fetch(new URL("api/model", base))).json();
const x = model.bounds.min.map((l, d) => 0.5 * (l + model.bounds.max[d]));
const requests = {
  export: ["/api/export", { x }],
  reference: ["/api/realtime/reference", { x, size: 256 }],
  map: ["/api/map", { layer: "albedo", x, rect: [model.bounds.min[0], model.bounds.max[0], model.bounds.min[1], model.bounds.max[1]], size: [128, 128] }],
};
if (!requests[o.kind]) throw new Error(`fairness_test: --kind must be one of ${Object.keys(requests).join(", ")}`);
const [path, body] = requests[o.kind];
const payload = JSON.stringify(body);

/// One POST from `localAddress`; resolves to { status, ms } (status 0: connection error).
function post(localAddress) {
  return new Promise((resolve) => {
    const t0 = performance.now();
    const req = http.request(
      { host: base.hostname, port: base.port || 80, path, method: "POST", localAddress, agent: false,
        headers: { "Content-Type": "application/json", "Content-Length": Buffer.byteLength(payload) },
        timeout: 60_000 },
      (res) => {
        res.on("data", () => {});
        res.on("end", () => resolve({ status: res.statusCode, ms: performance.now() - t0 }));
      });
    req.on("error", () => resolve({ status: 0, ms: performance.now() - t0 }));
    req.on("timeout", () => req.destroy());
    req.end(payload);
  });
}

const deadline = performance.now() + seconds * 1000;
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const groups = { flood: [], polite: [] };

async function loop(group, address, pause) {
  while (performance.now() < deadline) {
    const r = await post(address);
    groups[group].push(r);
    if (r.status === 503) await sleep(50);  // as a client honouring Retry-After would, briefly
    else if (pause > 0) await sleep(pause);
  }
}

const started = performance.now();
const tasks = [];
for (let i = 0; i < flood; ++i) tasks.push(loop("flood", "127.0.0.2", 0));
await sleep(500);  // the flood first: the polite clients arrive at a busy server
for (let i = 0; i < polite; ++i) tasks.push(loop("polite", `127.0.0.${3 + i}`, think));
await Promise.all(tasks);
const wall = (performance.now() - started) / 1000;

function summary(list) {
  const byStatus = {};
  for (const r of list) byStatus[r.status] = (byStatus[r.status] ?? 0) + 1;
  const ok = list.filter((r) => r.status === 200).map((r) => r.ms).sort((a, b) => a - b);
  const q = (p) => (ok.length ? ok[Math.min(ok.length - 1, Math.floor(p * ok.length))].toFixed(0) : "-");
  return { byStatus, answered: ok.length, p50: q(0.5), p95: q(0.95), max: ok.length ? ok.at(-1).toFixed(0) : "-" };
}
const f = summary(groups.flood), p = summary(groups.polite);
console.log(`fairness_test: ${o.kind} for ${wall.toFixed(1)} s, flood ${flood} concurrent from 127.0.0.2, ` +
            `${polite} polite clients (127.0.0.3..${2 + polite}, think ${think} ms)`);
for (const [name, s] of [["flood", f], ["polite", p]])
  console.log(`  ${name.padEnd(6)} answers ${JSON.stringify(s.byStatus)}; 200s: ${s.answered}, ` +
              `latency p50 ${s.p50} ms, p95 ${s.p95} ms, max ${s.max} ms`);
// A fair share of one slot among (1 + polite) clients: each polite client gets about 1/(1+polite)
// of the answers. Fail below a third of that.
const total = f.answered + p.answered;
const share = total > 0 ? p.answered / polite / total : 0;
console.log(`  polite share per client ${(100 * share).toFixed(1)} % of the answers (fair: ${(100 / (1 + polite)).toFixed(1)} %)`);
const politeErrors = groups.polite.filter((r) => r.status !== 200 && r.status !== 503).length;
process.exit(politeErrors > 0 || share < 1 / (3 * (1 + polite)) ? 1 : 0);
