// What a browser user sees on switching the preview to a scene (environment and/or object) the
// server has not prepared yet, against a running `matlas serve MODEL --port P` or `matlas demo`:
// the time from the switch to (a) the first image shown (the page shows the point rendered
// directly, POST /api/preview/refine, while the scene's preview basis is prepared) and (b) the
// server's basis image of that scene (POST /api/preview), and whether any request answered 503.
// No browser: it makes the page's requests itself, in the page's order and with its timings
// (docs/WEB.md "Preview", docs/API.md):
//
//   at the switch (the pickers commit 250 ms after the last change: web/src/scene.ts; the times
//   below start at the commit, and leave out the browser's PNG decode, a few ms):
//   - the preview card (web/src/preview.ts, scene-ready.ts, retry.ts): polls
//     GET /api/preview/status?env=&object= (0.25 s apart for the first 4 polls, then 0.6 s) until
//     `ready`; after its first not-ready answer and a 120 ms rest it refines the point, one
//     POST /api/preview/refine {x, env, object, seconds: 0.4, denoise: true} after the other (the
//     first answer with X-Matlas-Spp >= 1 is shown: time a); once ready, POST /api/preview
//     {x, env, object, size: preview.size}, retried on 503 after 0.4 s x 1.6^k (at most 3 s):
//     its answer is time b (and a, if no refined image came first);
//   - the library (web/src/library.ts): its own status poller (same schedule; both stop once
//     either sees the scene ready), then the thumbnails of the tiles in view (lazy images: how
//     many depends on the window; --thumbs N asks for the first N, 6 at a time; default none);
//   - the real-time card (web/src/realtime.ts, a browser with WebGL2; --no-realtime leaves it
//     out): GET /api/realtime/environment/ENV for an environment it has not loaded yet (once the
//     first image of the new scene shows, or after 3 s, as the page does), and
//     GET /api/realtime/mesh/OBJECT for an object other than the sphere it has not loaded yet.
// Before the first switch it does what the page does on opening: GET /api/model, the default
// scene's status and basis image of the point, GET /api/realtime and the default environment's
// maps. Between switches it waits for the requests in flight (the page at rest after the basis
// image; its refinement of the point, which the page continues, is not measured). A scene found
// ready at its first status poll (prepared already) is reported but not counted, and with
// --repeat an automatically picked one is replaced by the next candidate. Run it with no browser
// open on that server (a page's own requests would share the machine).
//
//   node bench/scene_switch.mjs [--url http://127.0.0.1:8080] [--env NAME] [--object NAME]
//                               [--point x,y] [--repeat N] [--thumbs N] [--no-realtime] [--timeout 900]
//
// --env/--object: the scene to switch to (either one alone: the other at the server's default,
// then, with --repeat, its other values; default: another environment, then another object, then
// both, from GET /api/model's lists). A scene is "not prepared" when the server does not hold its
// basis in memory: one in its cache folder (an earlier run, or dropped from memory) is loaded
// from disk rather than rendered, which the first switch of a fresh --cache folder shows.
// --point: the latent point (default: the first material's, where the page opens). --repeat N:
// N different not-yet-prepared scenes in turn (as many as the API offers), each reported, then
// the medians. Exit status 1, with the request and the server's message, on any HTTP error but
// the page's expected waits (503 on POST /api/preview, retried; 404 on the refinement: a server
// without rendered previews) or a switch without its basis image after --timeout seconds.
// Node 18+, no packages.
import { parseArgs } from "node:util";

const { values: o } = parseArgs({
  options: {
    url: { type: "string", default: "http://127.0.0.1:8080" },
    env: { type: "string" },
    object: { type: "string" },
    point: { type: "string" },
    repeat: { type: "string", default: "1" },
    thumbs: { type: "string", default: "0" },
    "no-realtime": { type: "boolean", default: false },
    timeout: { type: "string", default: "900" },
  },
});
const base = new URL(o.url.endsWith("/") ? o.url : `${o.url}/`);
const repeat = Math.max(1, Number(o.repeat) | 0), thumbs = Math.max(0, Number(o.thumbs) | 0);
const timeoutMs = 1000 * Number(o.timeout);

class ApiError extends Error {
  constructor(status, what, message) {
    super(`${what} answered ${status}: ${message}`);
    this.status = status;
  }
}
class Fatal extends Error {}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const ms = (v) => `${Math.round(v)} ms`;
const median = (v) => {
  const s = [...v].sort((a, b) => a - b), h = s.length >> 1;
  return s.length % 2 ? s[h] : (s[h - 1] + s[h]) / 2;
};

/** fetch as web/src/api.ts does (check(): a non-2xx answer throws its JSON `error`); the body read. */
async function call(method, path, body) {
  const what = `${method} /${path}`;
  let res;
  try {
    res = await fetch(new URL(path, base), body === undefined ? { method } : {
      method, headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
    });
  } catch (e) {
    throw new Fatal(`${what}: no answer from ${base.origin} (${e.cause?.code ?? e.cause?.message ?? e.message}); is the server running?`);
  }
  if (!res.ok) {
    let message = `${res.status} ${res.statusText}`;
    try {
      const j = await res.json();
      if (j && typeof j.error === "string") message = j.error;
    } catch {
      /* not JSON */
    }
    throw new ApiError(res.status, what, message);
  }
  const bytes = await res.arrayBuffer();
  return { headers: res.headers, bytes, json: () => JSON.parse(new TextDecoder().decode(bytes)) };
}
const q = (env, object) => `env=${encodeURIComponent(env)}&object=${encodeURIComponent(object)}`;

// ---- the page opens ---------------------------------------------------------------------------
const model = (await call("GET", "api/model").catch(die)).json();
const { envs, objects, default_env: defaultEnv, default_object: defaultObject } = model.scenes;
const x = o.point ? o.point.split(",").map(Number) : model.latent[0].slice();
if (x.length !== model.dim || !x.every(Number.isFinite))
  die(new Fatal(`--point needs ${model.dim} numbers (x1,...,x${model.dim}), not "${o.point}"`));
for (const [flag, name, list] of [["--env", o.env, envs], ["--object", o.object, objects]])
  if (name !== undefined && !list.includes(name)) die(new Fatal(`${flag} ${name}: the server offers ${list.join(", ")}`));

const ready = new Set();  // scene-ready.ts: the scenes this page has seen ready
/** scene-ready.ts sceneReady: polls the status until ready; onWait after every not-ready answer. */
async function sceneReady(env, object, count, onWait) {
  const key = `${env}/${object}`;
  for (let polls = 0; !ready.has(key); polls++) {
    const st = (await call("GET", `api/preview/status?${q(env, object)}`)).json();
    count?.(st);
    if (st.error) throw new Fatal(`the scene ${key} could not be prepared: ${st.error}`);
    if (st.ready) {
      ready.add(key);
      return;
    }
    onWait?.(st);
    await sleep(polls < 4 ? 250 : 600);
  }
}

let realtime = null;  // the real-time card: the environments and meshes it has loaded
let shown = { env: defaultEnv, object: defaultObject };  // the scene of the image on screen
try {
  await sceneReady(defaultEnv, defaultObject);
  await call("POST", "api/preview", { x, env: defaultEnv, object: defaultObject, size: model.preview.size });
  if (!o["no-realtime"]) {
    try {
      const info = (await call("GET", "api/realtime")).json();
      realtime = { info, env: defaultEnv, object: "sphere", envs: new Set(), meshes: new Set() };
      if (info.environments.includes(defaultEnv)) {
        await call("GET", `api/realtime/environment/${encodeURIComponent(defaultEnv)}`);
        realtime.envs.add(defaultEnv);
      }
      // syncScene at start-up: the top bar's object, if the card has it.
      if (defaultObject !== "sphere" && info.objects.includes(defaultObject)) {
        await call("GET", `api/realtime/mesh/${encodeURIComponent(defaultObject)}`);
        realtime.meshes.add(defaultObject);
        realtime.object = defaultObject;
      }
    } catch (e) {
      if (!(e instanceof ApiError)) throw e;
      console.log(`(the real-time card is off: ${e.message})`);  // the page shows the card's failure
      realtime = null;
    }
  }
} catch (e) {
  die(e);
}

// ---- the scenes to switch to ------------------------------------------------------------------
const candidates = [];
{
  const es = o.env !== undefined ? [o.env] : envs, os = o.object !== undefined ? [o.object] : objects;
  const add = (e, ob) => {
    if ((e !== defaultEnv || ob !== defaultObject) && !candidates.some((c) => c.env === e && c.object === ob))
      candidates.push({ env: e, object: ob });
  };
  const e0 = o.env ?? defaultEnv, ob0 = o.object ?? defaultObject;
  for (const e of es) add(e, ob0);  // another environment first,
  for (const ob of os) add(e0, ob);  // then another object,
  for (const e of es) for (const ob of os) add(e, ob);  // then both
  if (candidates.length === 0)
    die(new Fatal(`${e0}/${ob0} is the scene the page opens on: pass another --env or --object`));
}

// ---- one switch -------------------------------------------------------------------------------
async function switchTo(to) {
  const { env, object } = to;
  const t0 = performance.now();
  const now = () => performance.now() - t0;
  const s = { polls: 0, libraryPolls: 0, firstStatus: null, lastStatus: null, refines: 0, interrupted: 0, previews: 0, busy: 0,
    busyMessages: new Set(), thumbs: 0, thumbBusy: 0, first: null, firstKind: "", firstSpp: 0, ready: null, basis: null, extra: [] };
  let basisShown = false;
  let firstShown;
  const firstImage = new Promise((resolve) => (firstShown = resolve));
  let failWith;
  const failed = new Promise((_, reject) => (failWith = reject));
  const inflight = new Set();
  const track = (p) => {
    const t = p.catch(failWith);
    inflight.add(t);
    t.finally(() => inflight.delete(t));
    return t;
  };
  const countStatus = (st, library = false) => {
    if (library) s.libraryPolls++;
    else {
      s.polls++;
      s.firstStatus ??= st;  // the preview card's first answer: was the scene prepared already?
    }
    s.lastStatus = st;
  };

  // preview.ts refine(): one request after the other until the basis image (the page goes on until converged).
  let refining = null;
  const refine = async (r) => {
    await sleep(120);
    while (!basisShown) {
      let reply;
      try {
        reply = await call("POST", "api/preview/refine", { x, env, object, seconds: 0.4, denoise: true });
      } catch (e) {
        if (e instanceof ApiError && e.status === 404) {  // a server without rendered previews: the page stops quietly
          r.stopped = true;
          s.extra.push("refine 404");
          return;
        }
        throw e;
      }
      s.refines++;
      if (reply.headers.get("X-Matlas-Interrupted") === "1") s.interrupted++;
      if (basisShown) return;
      const spp = Number(reply.headers.get("X-Matlas-Spp") ?? 0);
      if (spp === 0) continue;  // interrupted before its first pass
      if (s.first === null) {  // least = 1: the image on screen is another scene's
        s.first = now();
        s.firstKind = "refined";
        s.firstSpp = spp;
        firstShown();
      }
      if (reply.headers.get("X-Matlas-Converged") === "1" && reply.headers.get("X-Matlas-Denoised") === "1") return;
    }
  };
  const startRefining = () => {
    if (refining && !refining.stopped) return;  // already refining this view
    refining = { stopped: false };
    track(refine(refining));
  };

  // preview.ts: LatestOnly task = waitForScene, then retryWhileBusy(api.preview).
  const previewCard = async () => {
    await sceneReady(env, object, countStatus, () => startRefining());
    s.ready = now();
    const start = performance.now();
    for (let delay = 400; ; delay = Math.min(3000, delay * 1.6)) {
      s.previews++;
      try {
        await call("POST", "api/preview", { x, env, object, size: model.preview.size });
        break;
      } catch (e) {
        if (!(e instanceof ApiError) || e.status !== 503 || performance.now() - start > 300_000) throw e;
        s.busy++;
        s.busyMessages.add(e.message);
        await sleep(delay);
      }
    }
    s.basis = now();
    basisShown = true;
    if (s.first === null) {
      s.first = s.basis;
      s.firstKind = "the basis";
      firstShown();
    }
  };

  // library.ts showThumbs: its own poller, then the tiles' thumbnails (--thumbs of them).
  const library = async () => {
    await sceneReady(env, object, (st) => countStatus(st, true));
    let next = 0;
    const worker = async () => {
      while (next < Math.min(thumbs, model.count)) {
        const i = next++;
        try {
          await call("GET", `api/thumbnail/${i}?${q(env, object)}`);
        } catch (e) {
          if (!(e instanceof ApiError) || e.status !== 503) throw e;
          s.thumbBusy++;  // a broken tile image in the page
        }
        s.thumbs++;
      }
    };
    await Promise.all(Array.from({ length: 6 }, worker));
  };

  // The store's listeners in the page's order: preview, library, real-time card.
  const main = track(previewCard());
  track(library());
  if (realtime) {
    if (realtime.info.environments.includes(env) && realtime.env !== env) {
      realtime.env = env;
      if (!realtime.envs.has(env)) {
        realtime.envs.add(env);
        // realtime.ts afterFirstImage: after the preview's first image of the environment, or 3 s.
        track(Promise.race([firstImage, sleep(3000)])
          .then(() => call("GET", `api/realtime/environment/${encodeURIComponent(env)}`))
          .then(() => s.extra.push(`real-time maps of ${env} after ${ms(now())}`)));
      }
    }
    const obj = object === "sphere" || realtime.info.objects.includes(object) ? object : "sphere";
    if (realtime.object !== obj) {
      realtime.object = obj;
      if (obj !== "sphere" && !realtime.meshes.has(obj)) {
        realtime.meshes.add(obj);
        track(call("GET", `api/realtime/mesh/${encodeURIComponent(obj)}`)
          .then(() => s.extra.push(`real-time mesh after ${ms(now())}`)));
      }
    }
  }
  let timer;
  const timeout = new Promise((_, reject) => {
    timer = setTimeout(() => reject(new Fatal(
      `no basis image of ${env}/${object} after ${o.timeout} s (last status: ${JSON.stringify(s.lastStatus)})`)), timeoutMs);
  });
  try {
    await Promise.race([main, failed, timeout]);
    while (inflight.size) await Promise.race([Promise.all(inflight), failed, timeout]);
  } finally {
    clearTimeout(timer);
  }
  return s;
}

function die(e) {
  if (e instanceof ApiError || e instanceof Fatal) {
    console.error(`scene_switch: ${e.message}`);
    process.exit(1);
  }
  throw e;
}

// ---- the switches -----------------------------------------------------------------------------
const firsts = [], bases = [];
let busyTotal = 0, skipped = 0, k = 0;
for (const to of candidates) {
  if (firsts.length === repeat) break;
  if (ready.has(`${to.env}/${to.object}`)) continue;  // seen ready by this run already
  const from = `${shown.env}/${shown.object}`;
  let s;
  try {
    s = await switchTo(to);
  } catch (e) {
    die(e);
  }
  shown = to;
  k++;
  const scene = `${from} -> ${to.env}/${to.object}`;
  const st = s.firstStatus;
  const status = st.ready ? "ready at once" : `first status "${st.stage}" ${Math.round(100 * st.progress)} %`;
  const busy = s.busy ? `${s.busy} x 503 on /api/preview (${[...s.busyMessages].join("; ")})` : "no 503";
  const tb = s.thumbBusy ? `, ${s.thumbBusy} x 503 on thumbnails` : "";
  const line = `switch ${k} ${scene}: first image ${ms(s.first)} (${s.firstKind}${s.firstKind === "refined" ? `, ${s.firstSpp} spp` : ""}), ` +
    `basis image ${ms(s.basis)} (ready seen at ${ms(s.ready)}); ${status}; ${s.polls} + ${s.libraryPolls} status polls (preview card + library), ${s.refines} refine request${s.refines === 1 ? "" : "s"}` +
    `${s.interrupted ? ` (${s.interrupted} interrupted)` : ""}, ${s.previews} preview request${s.previews > 1 ? "s" : ""}` +
    `${thumbs ? `, ${s.thumbs} thumbnails` : ""}; ${busy}${tb}${s.extra.length ? `; ${s.extra.join(", ")}` : ""}`;
  busyTotal += s.busy + s.thumbBusy;
  if (st.ready) {
    skipped++;
    console.log(`${line} -- prepared already: not counted`);
    if (o.env !== undefined && o.object !== undefined) break;
    continue;
  }
  console.log(line);
  firsts.push(s.first);
  bases.push(s.basis);
}
if (firsts.length === 0) die(new Fatal(`no scene the server had not prepared yet (${skipped} prepared already); ` +
  `restart the server or pick another scene with --env/--object`));
const range = (v) => v.length > 1 ? ` (min ${ms(Math.min(...v))}, max ${ms(Math.max(...v))})` : "";
console.log(`${firsts.length} switch${firsts.length > 1 ? "es" : ""} to a scene not prepared yet` +
  `${firsts.length < repeat ? ` (of ${repeat} asked: the API offers no more)` : ""}, n = ${model.count}, ` +
  `${model.preview.size} px: first image median ${ms(median(firsts))}${range(firsts)}, basis image median ` +
  `${ms(median(bases))}${range(bases)}; 503 answers: ${busyTotal}` +
  ` (times from the pickers' commit, 250 ms after the user's change)`);
