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
import { LatestOnly } from "./latest";
import { LocalWeights } from "./local-weights";
import { RealtimeGl } from "./realtime-gl";
import type { PageStore } from "./state";
import { clearError, setStatus } from "./status";

/** What the tests and the benchmark read (window.matlasViewer). */
export interface ViewerState {
  info: RealtimeInfo;
  gl: RealtimeGl;
  /** The point whose coefficients are shown, and the event time of the move that led to it. */
  shownX: number[] | null;
  /** Milliseconds from a map move to the frame showing it, newest last. */
  moveToFrame: number[];
  /** Whether that frame was a reduced one (drawn while dragging), per entry of moveToFrame. */
  moveToFrameReduced: boolean[];
  env: string;
  object: string;
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

export async function createRealtimeView(store: PageStore): Promise<ViewerState> {
  const canvas = $<HTMLCanvasElement>("rt-canvas");
  $("rt-info").textContent = "loading the coefficients (the server computes them from the model on first use)…";
  const t0 = performance.now();
  const [info, all, interpolation] = await Promise.all([api.realtime(), api.realtimeCoefficients(),
    api.interpolation().catch(() => null)]);
  // ?weights=server asks the server per move, as without the endpoint (for comparisons).
  const local = interpolation && new URLSearchParams(location.search).get("weights") !== "server"
    ? new LocalWeights(interpolation) : null;
  const coefficientsMs = performance.now() - t0;
  const gl = new RealtimeGl(canvas, info);
  const block = info.theta_o_count * info.coefficients * 3;
  const point = new Float32Array(block);
  const state: ViewerState = {
    info, gl, shownX: null, moveToFrame: [], moveToFrameReduced: [], env: "", object: "sphere", localWeights: !!local,
    loads: { coefficientsMs, environmentMs: {} },
  };
  window.matlasViewer = state;
  $("rt-info").textContent =
    `L = ${info.bands} · ${info.coefficients} lookups/pixel · ${info.materials} materials (${info.seconds.toFixed(1)} s on the server, ${Math.round(coefficientsMs)} ms to load)${local ? " · weights computed in the page" : ""}${gl.floatLinear ? "" : " · half-float textures"}`;

  // Map moves: the weights of the latest point, then the coefficients and a frame (drawn at once
  // while dragging).
  let movedAt = 0;
  const show = (w: ArrayLike<number>, x: number[], at: number) => {
    combineCoefficients(all, w, block, point);
    movedAt = at;
    gl.setCoefficients(point, store.state.dragging);
    state.shownX = x;
  };
  const weights = new LatestOnly<number[], number[]>(
    (x) => api.weights(x, 0).then((r) => r.weights), show,
    (e) => setStatus(`real-time view: ${(e as Error).message}`, true, "realtime"),
  );
  const request = (x: number[], at: number) => {
    if (!local) return weights.request(x, at);
    try {
      show(local.weights(x), x.slice(), at);
    } catch (e) {
      setStatus(`real-time view: ${(e as Error).message}`, true, "realtime");
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
    $("rt-fps").textContent = `${median(gl.frameTimes)} per frame · ${median(gl.fastFrameTimes)} while moving`;
  };
  store.on(["x"], (s) => request(s.x, s.movedAt));

  // Environment: each one's maps are fetched once.
  const envs = new Map<string, EnvironmentAtlas>();
  const envSelect = $<HTMLSelectElement>("rt-env");
  const setEnv = async (name: string) => {
    let atlas = envs.get(name);
    if (!atlas) {
      $("rt-info").dataset.loading = name;
      const start = performance.now();
      atlas = await api.realtimeEnvironment(name);
      state.loads.environmentMs[name] = performance.now() - start;
      envs.set(name, atlas);
    }
    if (envSelect.value !== name) return;  // another one was chosen meanwhile
    gl.setEnvironment(atlas);
    state.env = name;
    clearError("realtime");
  };
  fillSelect(envSelect, info.environments.map((e) => ({ value: e, label: e })), store.state.env);
  envSelect.addEventListener("change", () => setEnv(envSelect.value).catch(fail));

  // Object: the sphere, the served meshes (fetched once), or a user's .glb file.
  const objSelect = $<HTMLSelectElement>("rt-object");
  const meshes = new Map<string, Promise<import("three").Object3D>>();
  fillSelect(objSelect, ["sphere", ...info.objects.filter((o) => o !== "sphere")].map((o) => ({ value: o, label: o })), "sphere");
  objSelect.addEventListener("change", () => {
    const name = objSelect.value;
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
  });
  $<HTMLInputElement>("rt-file").addEventListener("change", async (ev) => {
    const file = (ev.target as HTMLInputElement).files?.[0];
    if (!file) return;
    try {
      gl.setObject(await RealtimeGl.meshFromGlb(await file.arrayBuffer()));
      state.object = file.name;
    } catch (e) {
      fail(new Error(`${file.name}: ${(e as Error).message} (Draco-compressed files are not supported)`));
    }
  });

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

  function fail(e: unknown): void {
    setStatus(`real-time view: ${(e as Error).message}`, true, "realtime");
  }

  await setEnv(envSelect.value);
  request(store.state.x, performance.now());
  return state;
}
