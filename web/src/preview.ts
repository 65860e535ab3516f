// The live preview: the server's image of the current point in the current scene. One request in
// flight, always the latest position (half-size while dragging, full size on release). Before the
// first image of a scene the page asks GET /api/preview/status: while the server prepares the
// scene it polls that (never retrying into 503s), shows the preparation's progress and time left,
// and meanwhile shows the refined image of the point (below), which needs no basis: a first image
// in a second or two. A new scene supersedes (aborts) the request in flight, so only the scene
// last chosen is ever shown. A 503 that still comes (a scene dropped from the server's memory)
// is retried with backoff.
import { api, ApiError, type PreviewStatus } from "./api";
import { $, showBlob } from "./dom";
import { LatestOnly } from "./latest";
import { waitForLayer } from "./map-panel";
import { retryWhileBusy, type Waiting } from "./retry";
import { sceneReady } from "./scene-ready";
import type { PageStore, ShownPreview } from "./state";
import { clearError, setStatus } from "./status";

export function createPreview(store: PageStore): void {
  const img = $<HTMLImageElement>("preview");
  const progress = $("preview-progress");
  const { size: fullSize, drag_size: dragSize } = store.state.model.preview;
  const refinedImg = $<HTMLImageElement>("preview-refined");
  const badge = $("preview-refine");
  const denoiseToggle = $<HTMLButtonElement>("preview-denoise");

  // --- refinement at rest ---
  let refining: AbortController | null = null;
  let refiningView = "";
  const stopRefining = () => {
    refining?.abort(new DOMException("moved", "AbortError"));
    refining = null;
    refiningView = "";
    refinedImg.hidden = true;
    badge.hidden = true;
    denoiseToggle.hidden = true;
    if (store.state.refined) store.update({ refined: null });
  };
  const sameView = (a: ShownPreview) => {
    const s = store.state;
    return !s.dragging && a.env === s.env && a.object === s.object && JSON.stringify(a.x) === JSON.stringify(s.x);
  };
  const refine = async (input: ShownPreview, signal: AbortSignal) => {
    await new Promise((resolve) => setTimeout(resolve, 120));  // a short rest first: a click-and-drag starts no refinement
    let shownSpp = 0;
    let shownDenoised: boolean | null = null;
    // Over a basis image of this scene, from the basis' sample count on (the first pass alone may
    // be noisier); over another scene's image (the scene is being prepared), from the first pass.
    const shown = store.state.shown;
    const least = shown && shown.env === input.env && shown.object === input.object ? 32 : 1;
    while (!signal.aborted && sameView(input)) {
      await waitForLayer(store.state.layerTiming, signal);
      if (signal.aborted || !sameView(input)) return;
      const r = await api.refine(input.x, input.env, input.object, 0.4, store.state.denoise, signal);
      if (signal.aborted || !sameView(input)) return;
      if (r.spp === 0) continue;  // interrupted before its first pass: nothing to show yet
      badge.hidden = false;
      badge.classList.toggle("converged", r.converged);
      const err = r.error === null ? "" : ` · ±${(100 * r.error).toFixed(r.error < 0.01 ? 2 : 1)} %`;
      badge.textContent = `${r.denoised ? "denoised · " : ""}${r.converged ? "converged" : "refining"} · ${r.spp} spp${err}`;
      if ((r.spp > shownSpp || r.denoised !== shownDenoised) && r.spp >= least) {
        await showBlob(refinedImg, r.blob);
        if (signal.aborted || !sameView(input)) return;
        refinedImg.hidden = false;
        denoiseToggle.hidden = false;
        shownSpp = r.spp;
        shownDenoised = r.denoised;
        store.update({ refined: { ...input, spp: r.spp, error: r.error, converged: r.converged, denoised: r.denoised },
          refinedImages: store.state.refinedImages + 1 });
      }
      if (r.converged && r.denoised === store.state.denoise) return;
    }
  };
  const startRefining = (input: ShownPreview) => {
    const view = JSON.stringify([input.x, input.env, input.object]);
    if (refining && view === refiningView && !refining.signal.aborted) return;  // already refining this view
    stopRefining();
    if (!store.state.refine || input.size !== fullSize || !sameView(input)) return;
    const controller = (refining = new AbortController());
    refiningView = view;
    refine(input, controller.signal).catch((e: unknown) => {
      if (refining === controller) refiningView = "";
      if (controller.signal.aborted) return;
      badge.hidden = true;
      if (e instanceof ApiError && e.status === 404) return;  // a server without rendered previews
      setStatus(`refinement: ${(e as Error).message}`, true, "refine");
    });
  };

  const bar = progress.querySelector<HTMLElement>(".bar span")!;
  const showWaiting = (input: ShownPreview, w: Waiting | null) => {
    progress.hidden = w === null;
    img.classList.toggle("stale", w !== null);
    store.update({ preparing: w && { env: input.env, object: input.object, attempts: w.attempts, waitedMs: w.waitedMs } });
    progress.classList.remove("determinate");
    bar.style.width = "";
    if (w) {
      progress.querySelector(".text")!.textContent =
        `preparing ${input.env} · ${input.object}: ${(w.waitedMs / 1000).toFixed(0)} s, attempt ${w.attempts + 1} in ${(w.delayMs / 1000).toFixed(1)} s`;
    }
  };
  /** Progress of a scene the server prepares (GET /api/preview/status). */
  const showPreparing = (input: ShownPreview, st: PreviewStatus, waitedMs: number, polls: number) => {
    progress.hidden = false;
    progress.classList.add("determinate");
    img.classList.add("stale");
    bar.style.width = `${(100 * st.progress).toFixed(1)}%`;
    const left = st.seconds_left === undefined ? "" : `, about ${Math.ceil(st.seconds_left)} s left`;
    progress.querySelector(".text")!.textContent = st.progress > 0
      ? `preparing ${input.env} · ${input.object}: ${Math.round(100 * st.progress)} %${left}`
      : `preparing ${input.env} · ${input.object}: ${st.stage}`;
    store.update({ preparing: { env: input.env, object: input.object, attempts: polls, waitedMs } });
  };
  /** Resolves once the scene of `input` is ready, showing its progress and refining meanwhile. */
  const waitForScene = (input: ShownPreview, signal: AbortSignal) =>
    sceneReady(input.env, input.object, signal, (st, waitedMs, polls) => {
      showPreparing(input, st, waitedMs, polls);
      startRefining({ ...input, size: fullSize });  // a first image of the point while the basis renders
    });

  const preview = new LatestOnly<ShownPreview, Blob>(
    async (input, signal) => {
      await waitForScene(input, signal);
      return retryWhileBusy((s) => api.preview(input.x, input.env, input.object, input.size, s),
        { signal, onWait: (w) => showWaiting(input, w) });
    },
    async (blob, input, startedAt) => {
      await showBlob(img, blob);
      showWaiting(input, null);
      clearError("preview");
      const s = store.state;
      const scene = `${input.env}/${input.object}`;
      if (s.shownScenes[s.shownScenes.length - 1] !== scene) s.shownScenes.push(scene);
      const ms = performance.now() - startedAt;
      s.latencies.push(ms);
      if (s.latencies.length > 500) s.latencies.shift();
      store.update({ shown: input, previews: s.previews + 1 });
      const recent = s.latencies.slice(-30).sort((a, b) => a - b);
      $("latency").textContent = `${Math.round(ms)} ms · median ${Math.round(recent[recent.length >> 1])} ms`;
      img.dataset.x = JSON.stringify(input.x);
      img.dataset.size = String(input.size);
      clearError("refine");
      startRefining(input);
    },
    (e) => {
      progress.hidden = true;
      img.classList.remove("stale");
      store.update({ preparing: null });
      setStatus(`preview: ${(e as Error).message}`, true, "preview");
    },
  );

  const current = (size: number): ShownPreview => {
    const s = store.state;
    return { x: s.x, size, env: s.env, object: s.object };
  };
  store.on(["x"], (s) => {
    stopRefining();
    preview.request(current(s.dragging ? dragSize : fullSize), s.movedAt);
  });
  store.on(["env", "object"], () => {
    stopRefining();
    preview.request(current(fullSize), performance.now(), true);
  });
  store.on(["dragging"], (s) => s.dragging && stopRefining());
  store.on(["refine"], (s) => (s.refine && s.shown ? startRefining(s.shown) : stopRefining()));
  // The denoiser on or off: the same refinement (its samples stay on the server), shown the other way.
  denoiseToggle.addEventListener("click", () => store.update({ denoise: !store.state.denoise }));
  store.on(["denoise"], (s) => {
    denoiseToggle.setAttribute("aria-pressed", String(s.denoise));
    denoiseToggle.classList.toggle("on", s.denoise);
    if (s.refine && s.shown) {
      stopRefining();
      startRefining(s.shown);
    }
  });
}
