// The live preview: the server's image of the current point in the current scene. One request in
// flight, always the latest position (half-size while dragging, full size on release). While the
// server prepares a scene (503), the request is retried with backoff and the preview shows how
// long it has been waiting; a new scene supersedes (aborts) the request in flight, so only the
// scene last chosen is ever shown.
import { api, ApiError } from "./api";
import { $, showBlob } from "./dom";
import { LatestOnly } from "./latest";
import { retryWhileBusy, type Waiting } from "./retry";
import type { PageStore, ShownPreview } from "./state";
import { clearError, setStatus } from "./status";

export function createPreview(store: PageStore): void {
  const img = $<HTMLImageElement>("preview");
  const progress = $("preview-progress");
  const { size: fullSize, drag_size: dragSize } = store.state.model.preview;
  const refinedImg = $<HTMLImageElement>("preview-refined");
  const badge = $("preview-refine");

  // --- refinement at rest ---
  let refining: AbortController | null = null;
  const stopRefining = () => {
    refining?.abort(new DOMException("moved", "AbortError"));
    refining = null;
    refinedImg.hidden = true;
    badge.hidden = true;
    if (store.state.refined) store.update({ refined: null });
  };
  const sameView = (a: ShownPreview) => {
    const s = store.state;
    return !s.dragging && a.env === s.env && a.object === s.object && JSON.stringify(a.x) === JSON.stringify(s.x);
  };
  const refine = async (input: ShownPreview, signal: AbortSignal) => {
    await new Promise((resolve) => setTimeout(resolve, 120));  // a short rest first: a click-and-drag starts no refinement
    let shownSpp = 0;
    while (!signal.aborted && sameView(input)) {
      const r = await api.refine(input.x, input.env, input.object, 0.4, signal);
      if (signal.aborted || !sameView(input)) return;
      badge.hidden = false;
      badge.classList.toggle("converged", r.converged);
      const err = r.error === null ? "" : ` · ±${(100 * r.error).toFixed(r.error < 0.01 ? 2 : 1)} %`;
      badge.textContent = `${r.converged ? "converged" : "refining"} · ${r.spp} spp${err}`;
      if (r.spp > shownSpp && r.spp >= 32) {  // from the basis' sample count on (the first pass alone may be noisier)
        await showBlob(refinedImg, r.blob);
        if (signal.aborted || !sameView(input)) return;
        refinedImg.hidden = false;
        shownSpp = r.spp;
        store.update({ refined: { ...input, spp: r.spp, error: r.error, converged: r.converged }, refinedImages: store.state.refinedImages + 1 });
      }
      if (r.converged) return;
    }
  };
  const startRefining = (input: ShownPreview) => {
    stopRefining();
    if (!store.state.refine || input.size !== fullSize || !sameView(input)) return;
    const controller = (refining = new AbortController());
    refine(input, controller.signal).catch((e: unknown) => {
      if (controller.signal.aborted) return;
      badge.hidden = true;
      // 404: a server without rendered previews; 409: a newer request of ours cancelled it.
      if (e instanceof ApiError && (e.status === 404 || e.status === 409)) return;
      setStatus(`refinement: ${(e as Error).message}`, true, "refine");
    });
  };

  const showWaiting = (input: ShownPreview, w: Waiting | null) => {
    progress.hidden = w === null;
    img.classList.toggle("stale", w !== null);
    store.update({ preparing: w && { env: input.env, object: input.object, attempts: w.attempts, waitedMs: w.waitedMs } });
    if (w) {
      progress.querySelector(".text")!.textContent =
        `preparing ${input.env} · ${input.object}: ${(w.waitedMs / 1000).toFixed(0)} s, attempt ${w.attempts + 1} in ${(w.delayMs / 1000).toFixed(1)} s`;
    }
  };

  const preview = new LatestOnly<ShownPreview, Blob>(
    (input, signal) => retryWhileBusy(
      (s) => api.preview(input.x, input.env, input.object, input.size, s),
      { signal, onWait: (w) => showWaiting(input, w) }),
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
}
