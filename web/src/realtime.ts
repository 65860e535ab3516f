// The real-time view (issue 12): the current map point shaded by the rotated-ZH shader under a
// prefiltered environment, beside the path-traced preview (the "reference render"). The page
// fetches every material's coefficients once (GET /api/realtime/coefficients) and an
// environment's band maps once per environment; a map move computes the weights in the page
// (local-weights.ts, from GET /api/interpolation; a server without it is asked for them, one
// request in flight, the latest point) and combines the coefficients there:
// mean + sum_i w_i (lambda_i - mean), so that the frame follows the pointer without a round trip. Camera (orbit), environment rotation, exposure, bands,
// environment and object change without the server (a new environment's maps, a served mesh
// and the first coefficients are fetched once each, then kept).
import { api, type EnvironmentAtlas, type RealtimeInfo } from "./api";
import { $, fillSelect } from "./dom";
import { DragThrottle } from "./drag-throttle";
import { LatestOnly } from "./latest";
import { LocalWeights } from "./local-weights";
import { waitForQuietMap } from "./map-panel";
import { RealtimeGl } from "./realtime-gl";
import type { PageStore } from "./state";
import { clearError } from "./status";

/** What the tests and the benchmark read (window.matlasViewer). */
export interface ViewerState {
  info: RealtimeInfo;
  gl: RealtimeGl;
  /** The point whose coefficients are shown, and the event time of the move that led to it. */
  shownX: number[] | null;
  /** The point whose light table the direct lights use (it follows shownX a request behind). */
  lightsX: number[] | null;
  /** Milliseconds from a map move to the frame showing it, newest last. */
  moveToFrame: number[];
  /** Whether that frame was a reduced one (drawn while dragging), per entry of moveToFrame. */
  moveToFrameReduced: boolean[];
  env: string;
  object: string;
  /** Whether the view has its own scene ("own scene"), else the top bar's. */
  ownScene: boolean;
  /** Whether the weights are computed in the page (else asked of the server per move). */
  localWeights: boolean;
  loads: { coefficientsMs: number; environmentMs: Record<string, number> };
}

declare global {
  interface Window {
    matlasViewer?: ViewerState;
  }
}

/** mean + sum_i w_i (lambda_i - mean) = (1 - sum w) mean + sum_i w_i lambda_i, into out. */
export function combineCoefficients(all: Float32Array, w: ArrayLike<number>, block: number, out: Float32Array): void {
  let sum = 0;
  for (let i = 0; i < w.length; ++i) sum += w[i];
  for (let v = 0; v < block; ++v) out[v] = (1 - sum) * all[v];
  for (let i = 0; i < w.length; ++i) {
    const wi = w[i];
    if (wi === 0) continue;
    const base = (i + 1) * block;
    for (let v = 0; v < block; ++v) out[v] += wi * all[base + v];
  }
}

/** Whether this browser gives a WebGL2 context (the viewer needs one). */
function hasWebGl2(): boolean {
  try {
    return !!document.createElement("canvas").getContext("webgl2");
  } catch {
    return false;
  }
}

/** GET api/realtime/coefficients, reporting the bytes received (Content-Length) as they come. */
async function fetchCoefficients(onBytes: (got: number, total: number) => void): Promise<Float32Array> {
  const r = await fetch("api/realtime/coefficients");
  if (!r.ok || !r.body) return api.realtimeCoefficients();  // the error (or a body-less answer) as the client reports it
  const total = Number(r.headers.get("Content-Length") ?? 0);
  const parts: Uint8Array[] = [];
  let got = 0;
  const reader = r.body.getReader();
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    parts.push(value);
    got += value.length;
    onBytes(got, total);
  }
  const all = new Uint8Array(got);
  let o = 0;
  for (const p of parts) {
    all.set(p, o);
    o += p.length;
  }
  return new Float32Array(all.buffer, 0, got >> 2);
}

/**
 * The card's own progress and errors: a bar with what is being waited for (and for how long),
 * and an error box over the canvas (no WebGL2, coefficients or maps that failed), so that the card
 * never says "loading" forever and its errors show where they happen.
 */
class CardStatus {
  private readonly progress = $("rt-progress");
  private readonly error = $("rt-error");
  private timer = 0;

  waiting(text: (seconds: number) => string, fraction: number | null = null): void {
    const start = performance.now();
    clearInterval(this.timer);
    const show = () => {
      this.progress.querySelector(".text")!.textContent = text((performance.now() - start) / 1000);
    };
    this.fraction(fraction);
    show();
    this.progress.hidden = false;
    this.timer = window.setInterval(show, 500);
  }

  fraction(f: number | null): void {
    const bar = this.progress.querySelector(".bar")!;
    bar.classList.toggle("busy", f === null);
    (bar.firstElementChild as HTMLElement).style.width = f === null ? "" : `${(100 * f).toFixed(1)}%`;
  }

  done(): void {
    clearInterval(this.timer);
    this.progress.hidden = true;
  }

  private source = "";

  /** Shows `message` over the canvas; `source`: what a later success of the same kind clears. */
  fail(message: string, source = "start"): void {
    this.done();
    this.error.textContent = message;
    this.error.hidden = false;
    this.source = source;
    if (source === "start") {
      // Nothing in the card can act: its controls say so by being disabled.
      $("rt-info").textContent = "";
      document.querySelectorAll<HTMLInputElement>(".realtime-card input, .realtime-card select, .realtime-card button")
        .forEach((el) => (el.disabled = true));
      document.querySelector(".realtime-card label.button")?.classList.add("disabled");
    }
  }

  /** A success of `source` (or of anything, without it): its error is stale. */
  clear(source?: string): void {
    if (source === undefined || source === this.source) this.error.hidden = true;
  }
}

/** The real-time card; its failures show in the card (never rejects: null when it cannot run). */
export async function createRealtimeView(store: PageStore): Promise<ViewerState | null> {
  const card = new CardStatus();
  if (!hasWebGl2()) {
    card.fail("The real-time view needs WebGL2, which this browser does not offer (disabled, or no GPU " +
      "driver). The reference render beside it does not need it.");
    return null;
  }
  try {
    return await startRealtimeView(store, card);
  } catch (e) {
    card.fail(`The real-time view could not start: ${(e as Error).message}`);
    return null;
  }
}

/** How long the map must have had no layer on its way before the card starts loading. */
const MAP_QUIET_MS = 300;
/** While dragging, the light table of the point (729 KB, about 30 ms of the server's time at
 *  n = 1000) at most this often: one per pointer event held the page's cores (the 1000-material
 *  drag's preview median 212-228 -> 130-179 ms on the 2-core VM, docs/BENCHMARKS.md "Real-time
 *  viewer"). */
const LIGHTS_DRAG_MS = 250;

/** The most materials for which the page computes the weights itself (local-weights.ts). */
const LOCAL_WEIGHTS_MAX = 300;

async function startRealtimeView(store: PageStore, card: CardStatus): Promise<ViewerState> {
  const canvas = $<HTMLCanvasElement>("rt-canvas");
  $("rt-info").textContent = "";
  card.waiting((t) => `waiting for the map's layer: ${t.toFixed(0)} s`);
  await waitForQuietMap(store.state.layerTiming, MAP_QUIET_MS);
  card.waiting((t) => `the server computes the real-time coefficients of every material (once per model): ${t.toFixed(0)} s`);
  const t0 = performance.now();
  // Weights in the page only where they are cheap: the state is 2 n^2 numbers (33 MB of JSON at
  // n = 1000) and each convex step refactorises its active set (O(|F|^3) in JavaScript, hundreds
  // of coefficients at n = 1000: seconds per move, the page stops responding); beyond
  // LOCAL_WEIGHTS_MAX materials the server solves each point (warm-started from the last one).
  const interpolationP = store.state.model.count <= LOCAL_WEIGHTS_MAX ? api.interpolation().catch(() => null) : Promise.resolve(null);
  const info = await api.realtime();
  card.waiting((t) => `loading the coefficients: ${t.toFixed(0)} s`, 0);
  const all = await fetchCoefficients((got, total) => {
    if (total > 0) card.fraction(got / total);
  }).catch((e: Error) => {
    throw new Error(`the coefficients failed to load (${e.message})`);
  });
  const interpolation = await interpolationP;
  card.done();
  // ?weights=server asks the server per move, as without the endpoint (for comparisons).
  const local = interpolation && new URLSearchParams(location.search).get("weights") !== "server"
    ? new LocalWeights(interpolation) : null;
  const coefficientsMs = performance.now() - t0;
  const gl = new RealtimeGl(canvas, info);
  const block = info.theta_o_count * info.coefficients * 3;
  const point = new Float32Array(block);
  const state: ViewerState = {
    info, gl, shownX: null, lightsX: null, moveToFrame: [], moveToFrameReduced: [], env: "", object: "sphere", ownScene: false, localWeights: !!local,
    loads: { coefficientsMs, environmentMs: {} },
  };
  window.matlasViewer = state;
  const rtInfo = $("rt-info");
  const infoText = (lights: number) =>
    `L = ${info.bands} · ${info.coefficients} lookups/pixel${lights ? ` + ${lights} lights` : ""} · ready in ` +
    `${(info.seconds + coefficientsMs / 1000).toFixed(1)} s${gl.floatLinear ? "" : " · half-float textures"}`;
  rtInfo.textContent = infoText(0);
  rtInfo.title = `${info.materials} materials' coefficients: ${info.seconds.toFixed(1)} s on the server, ` +
    `${Math.round(coefficientsMs)} ms to load${local ? "; weights computed in the page" : "; weights asked of the server"}`;

  // The direct lights' light table of the latest point shown, asked of the server (one request in
  // flight, the newest point): until it comes, the frames keep the previous point's.
  const lightTables = new LatestOnly<number[], Uint16Array>(
    (x) => api.realtimeLights(x),
    (bits, x) => {
      gl.setLightTable(bits, store.state.dragging);
      state.lightsX = x;
      card.clear("lights");
    },
    (e) => fail(e, "lights"),
  );

  // While dragging, the light table is asked at most every LIGHTS_DRAG_MS (the frames meanwhile
  // use the last one); at rest, at once.
  const lightsThrottle = new DragThrottle<{ x: number[]; at: number }>(LIGHTS_DRAG_MS, ({ x, at }) => lightTables.request(x, at));

  // Map moves: the weights of the latest point, then the coefficients and a frame (drawn at once
  // while dragging).
  let movedAt = 0;
  const show = (w: ArrayLike<number>, x: number[], at: number) => {
    combineCoefficients(all, w, block, point);
    movedAt = at;
    gl.setCoefficients(point, store.state.dragging);
    state.shownX = x;
    card.clear("move");  // an earlier move's failure is stale
    lightsThrottle.request({ x: x.slice(), at }, store.state.dragging);
  };
  const weights = new LatestOnly<number[], number[]>(
    (x) => api.weights(x, 0).then((r) => r.weights), show, (e) => fail(e, "move"),
  );
  const request = (x: number[], at: number) => {
    if (!local) return weights.request(x, at);
    try {
      show(local.weights(x), x.slice(), at);
    } catch (e) {
      fail(e, "move");
    }
  };
  const median = (v: number[]) => {
    const s = v.slice(-30).sort((a, b) => a - b);
    return s.length ? `${s[s.length >> 1].toFixed(0)} ms` : "–";
  };
  gl.onFrame = (end, fast) => {
    if (movedAt) {  // the first frame (reduced or not) with the new coefficients
      state.moveToFrame.push(end - movedAt);
      state.moveToFrameReduced.push(fast);
      if (state.moveToFrame.length > 500) {
        state.moveToFrame.shift();
        state.moveToFrameReduced.shift();
      }
      movedAt = 0;
    }
    $("rt-fps").textContent = `${median(gl.frameTimes)}/frame · ${median(gl.fastFrameTimes)} moving`;
    $("rt-fps").title = "median frame time, at rest and while the point or camera moves";
  };
  store.on(["x"], (s) => request(s.x, s.movedAt));

  // Environment: each one's maps are fetched once (with progress in the card).
  const envs = new Map<string, EnvironmentAtlas>();
  const envSelect = $<HTMLSelectElement>("rt-env");
  const setEnv = async (name: string) => {
    let atlas = envs.get(name);
    if (!atlas) {
      $("rt-info").dataset.loading = name;
      const start = performance.now();
      card.waiting((t) => `loading the ${name} environment's maps: ${t.toFixed(0)} s`);
      try {
        atlas = await api.realtimeEnvironment(name);
      } finally {
        card.done();
      }
      state.loads.environmentMs[name] = performance.now() - start;
      envs.set(name, atlas);
    }
    if (envSelect.value !== name) return;  // another one was chosen meanwhile
    gl.setEnvironment(atlas);
    rtInfo.textContent = infoText(atlas.lights?.count ?? 0);
    state.env = name;
    card.clear();
    clearError("realtime");
  };
  fillSelect(envSelect, info.environments.map((e) => ({ value: e, label: e })), store.state.env);
  envSelect.addEventListener("change", () => setEnv(envSelect.value).catch(fail));

  // Object: the sphere, the served meshes (fetched once), or a user's .glb file.
  const objSelect = $<HTMLSelectElement>("rt-object");
  const meshes = new Map<string, Promise<import("three").Object3D>>();
  fillSelect(objSelect, ["sphere", ...info.objects.filter((o) => o !== "sphere")].map((o) => ({ value: o, label: o })), "sphere");
  const setObject = (name: string) => {
    if (name === "sphere") {
      meshes.set(name, meshes.get(name) ?? Promise.resolve(RealtimeGl.sphere()));
    } else if (!meshes.has(name)) {
      meshes.set(name, api.realtimeMesh(name).then(RealtimeGl.meshFromBuffer));
    }
    meshes.get(name)!.then((o) => {
      if (objSelect.value !== name) return;
      gl.setObject(o);
      state.object = name;
    }).catch(fail);
  };
  objSelect.addEventListener("change", () => setObject(objSelect.value));
  const own = $<HTMLInputElement>("rt-own");
  $<HTMLInputElement>("rt-file").addEventListener("change", async (ev) => {
    const file = (ev.target as HTMLInputElement).files?.[0];
    if (!file) return;
    try {
      const mesh = await RealtimeGl.meshFromGlb(await file.arrayBuffer());
      own.checked = true;  // a file of the user's: this view's own scene from now on
      syncScene();
      gl.setObject(mesh);
      state.object = file.name;
    } catch (e) {
      fail(new Error(`${file.name}: ${(e as Error).message} (Draco-compressed files are not supported)`));
    }
  });

  // A new environment's maps are asked for once the preview shows its first image of that
  // environment, or after 3 s: the server would otherwise prefilter them while it renders that
  // first image, and the preview is what the user looks at first (bench/scene_switch.mjs).
  const afterFirstImage = (env: string) => new Promise<void>((resolve) => {
    const shown = () => store.state.shown?.env === env || store.state.refined?.env === env;
    if (shown() || envs.has(env)) return resolve();
    const finish = () => {
      clearTimeout(timer);
      off();
      resolve();
    };
    const timer = setTimeout(finish, 3000);
    const off = store.on(["shown", "refined"], () => shown() && finish());
  });

  // One set of scene controls: the top bar's environment and object drive this view too, unless
  // the user turns on "own scene" (then its pickers apply; off again: back to the top bar's).
  const syncScene = () => {
    envSelect.disabled = objSelect.disabled = !own.checked;
    state.ownScene = own.checked;
    if (own.checked) return;
    const { env, object } = store.state;
    if (info.environments.includes(env) && envSelect.value !== env) {
      envSelect.value = env;
      afterFirstImage(env).then(() => setEnv(env)).catch(fail);
    }
    const obj = object === "sphere" || info.objects.includes(object) ? object : "sphere";
    if (objSelect.value !== obj || state.object !== obj) {
      objSelect.value = obj;
      setObject(obj);
    }
  };
  own.addEventListener("change", syncScene);
  store.on(["env", "object"], syncScene);

  const slider = (id: string, apply: (v: number) => void, fmt: (v: number) => string) => {
    const input = $<HTMLInputElement>(id);
    const out = $(`${id}-out`);
    const set = () => {
      apply(Number(input.value));
      out.textContent = fmt(Number(input.value));
    };
    input.addEventListener("input", set);
    set();
  };
  slider("rt-rotation", (v) => gl.setRotation(v, true), (v) => `${v}°`);
  slider("rt-exposure", (v) => gl.setExposure(v), (v) => `${v > 0 ? "+" : ""}${v}`);
  const bands = $<HTMLInputElement>("rt-bands");
  bands.max = String(info.bands);
  bands.value = String(info.bands);
  slider("rt-bands", (v) => gl.setBands(v), (v) => `L = ${v}`);
  $("rt-reset").addEventListener("click", () => gl.resetCamera());

  function fail(e: unknown, source = "scene"): void {
    card.fail(`real-time view: ${(e as Error).message}`, source);
  }

  await setEnv(envSelect.value);
  syncScene();
  request(store.state.x, performance.now());
  return state;
}
