// The scene view (docs/GI.md, docs/WEB.md): the material of the current point on an object of a
// path-traced scene (floor, box), composed by the server from a GI image basis (GET /api/gi)
// and updated while dragging: one request in flight, always for the newest point (latest.ts).
// Exposure is automatic by default (the scene's key with the mean material, one value for the
// whole map); moving the slider sets it by hand; the tone curve is filmic (ACES) by default.
// A scene is off until picked, unless the server was given its basis (then the first such scene
// is shown at once); while the server traces a picked scene (503), the view retries and shows the
// server's progress (retry.ts); picking another scene supersedes the request in flight.
// The view picker offers the built-in scenes' cameras (each view, "SCENE@VIEW", a scene of its own).
// Refinement at rest: once the composed image of a point is shown and the pointer rests, the page
// asks POST /api/gi/refine again and again (1 s each, 2 s from 5 s of rest on); the server path-traces the point directly at full size
// (512 x 384 by default), pass after pass, and the page lays the refined image over the composed
// one from 4 spp on (as many samples per unit of image as the 256 x 192, 16-spp basis). The refined
// image is never mixed with the composed one. It is denoised as the previews are (the same
// "denoise" setting, a toggle on each view: the server's dual-buffer filter, biased, labelled in the
// badge). Moving the point, the scene, view, exposure or tone hides it and stops the refinement
// (the next GET /api/gi also stops the server's pass).
import { api } from "./api";
import { $, fillSelect, showBlob } from "./dom";
import { LatestOnly } from "./latest";
import { waitForLayer } from "./map-panel";
import { retryWhileBusy, type Waiting } from "./retry";
import type { PageState, PageStore } from "./state";
import { clearError, setStatus } from "./status";

/** What the view shows: a point in a scene at an exposure and tone curve (as the page state keeps it). */
type GiInput = NonNullable<PageState["giShown"]>;

export function createGiView(store: PageStore): void {
  const gi = store.state.model.gi;
  if (!gi || gi.scenes.length === 0) return;  // the server has no scenes: the view stays hidden
  $("gi-view").hidden = false;
  const sel = $<HTMLSelectElement>("gi-scene"), img = $<HTMLImageElement>("gi"), progress = $("gi-progress");
  const info = $("gi-info");
  const camera = $<HTMLSelectElement>("gi-camera"), refinedImg = $<HTMLImageElement>("gi-refined"), badge = $("gi-refine");
  const denoiseToggle = $<HTMLButtonElement>("gi-denoise");
  const auto = $<HTMLInputElement>("gi-auto"), exposure = $<HTMLInputElement>("gi-exposure");
  const exposureValue = $("gi-exposure-value"), tone = $<HTMLSelectElement>("gi-tone");
  const showExposure = (stops: number) => {
    exposure.value = String(stops);
    exposureValue.textContent = `${stops >= 0 ? "+" : ""}${stops.toFixed(2)}`;
  };
  fillSelect(sel, [{ value: "", label: "off" }, ...gi.scenes.map((s) => ({ value: s, label: s }))], gi.preloaded[0] ?? "");
  const views = gi.views ?? {};
  const fillViews = () => {
    const list = views[sel.value] ?? [];
    fillSelect(camera, list.length ? list.map((v) => ({ value: v, label: v })) : [{ value: "", label: "—" }], list[0] ?? "");
    camera.disabled = list.length < 2;
  };
  fillViews();
  /** The scene asked for: the picked scene, or its view "SCENE@VIEW" (the first view is the scene's own). */
  const sceneName = () => {
    const list = views[sel.value] ?? [];
    return sel.value && camera.value && camera.value !== list[0] ? `${sel.value}@${camera.value}` : sel.value;
  };

  // --- refinement at rest ---
  let refining: AbortController | null = null;
  let refiningKey = "";
  const stopRefining = () => {
    refining?.abort(new DOMException("moved", "AbortError"));
    refining = null;
    refiningKey = "";
    refinedImg.hidden = true;
    badge.hidden = true;
    denoiseToggle.hidden = true;
    if (store.state.giRefined) store.update({ giRefined: null });
  };
  const current = (input: GiInput) => {
    const s = store.state;
    return !s.dragging && sceneName() === input.scene && JSON.stringify(s.x) === JSON.stringify(input.x) &&
      input.tone === tone.value && (input.exposure === "auto") === auto.checked &&
      (input.exposure === "auto" || input.exposure === Number(exposure.value));
  };
  const refine = async (input: GiInput, signal: AbortSignal) => {
    await new Promise((resolve) => setTimeout(resolve, 150));  // a short rest first: a drag starts no refinement
    let shownSpp = 0, shownDenoised: boolean | null = null;
    const denoise = store.state.denoise, restedAt = performance.now();
    while (!signal.aborted && current(input)) {
      await waitForLayer(store.state.layerTiming, signal);
      if (signal.aborted || !current(input)) return;
      // Steps of 1 s, from 5 s of rest on 2 s: each answer is denoised (about 0.4 s at 512 x 384 on
      // two cores), which longer steps leave more of the time to trace (docs/GI.md).
      const seconds = performance.now() - restedAt < 5000 ? 1.0 : 2.0;
      const r = await api.giRefine(input.scene, input.x, input.exposure, input.tone, seconds, denoise, signal);
      if (signal.aborted || !current(input)) return;
      if (r.spp === 0) continue;
      badge.hidden = false;
      badge.classList.toggle("converged", r.converged);
      const err = r.error === null ? "" : ` · ±${(100 * r.error).toFixed(r.error < 0.01 ? 2 : 1)} %`;
      badge.textContent = `${r.denoised ? "denoised · " : ""}${r.converged ? "converged" : "refining"} · ${r.spp} spp${err}`;
      if ((r.spp > shownSpp || r.denoised !== shownDenoised) && r.spp >= 4) {
        await showBlob(refinedImg, r.blob);
        if (signal.aborted || !current(input)) return;
        refinedImg.hidden = false;
        denoiseToggle.hidden = false;
        shownSpp = r.spp;
        shownDenoised = r.denoised;
        refinedImg.dataset.spp = String(r.spp);
        info.textContent = `${refinedImg.naturalWidth}×${refinedImg.naturalHeight} · ${r.spp} spp`;
        store.update({
          giRefined: { x: input.x, scene: input.scene, spp: r.spp, error: r.error, converged: r.converged, denoised: r.denoised },
          giRefinedImages: store.state.giRefinedImages + 1,
        });
      }
      if (r.converged && r.denoised === denoise) return;
    }
  };
  const startRefining = (input: GiInput) => {
    const key = JSON.stringify(input);
    if (refining && key === refiningKey && !refining.signal.aborted) return;
    stopRefining();
    if (!current(input)) return;
    const controller = (refining = new AbortController());
    refiningKey = key;
    refine(input, controller.signal).catch((e: unknown) => {
      if (refining === controller) refiningKey = "";
      if (controller.signal.aborted) return;
      badge.hidden = true;
      setStatus(`scene refinement: ${(e as Error).message}`, true, "gi-refine");
    });
  };

  const showWaiting = (w: Waiting | null) => {
    if (!sel.value) w = null;  // switched off: a retry still under way shows nothing
    progress.hidden = w === null;
    img.classList.toggle("stale", w !== null);
    if (w) progress.querySelector(".text")!.textContent = `${w.message} (${(w.waitedMs / 1000).toFixed(0)} s)`;
  };

  const view = new LatestOnly<GiInput, { blob: Blob; exposure: number }>(
    (input, signal) => retryWhileBusy((s) => api.gi(input.scene, input.x, input.exposure, input.tone, s),
      { signal, onWait: showWaiting, firstDelayMs: 500, maxDelayMs: 2000, giveUpMs: 1_800_000 }),
    async ({ blob, exposure: used }, input, startedAt) => {
      if (sceneName() !== input.scene) return;  // switched off or to another view meanwhile
      await showBlob(img, blob);
      if (input.exposure === "auto" && auto.checked) showExposure(used);
      img.dataset.exposure = String(used);
      img.hidden = false;
      showWaiting(null);
      clearError("gi");
      info.textContent = `${img.naturalWidth}×${img.naturalHeight} · ${Math.round(performance.now() - startedAt)} ms`;
      img.dataset.x = JSON.stringify(input.x);
      img.dataset.scene = input.scene;
      store.update({ giShown: input, giImages: store.state.giImages + 1 });
      startRefining(input);
    },
    (e) => {
      showWaiting(null);
      setStatus(`scene view: ${(e as Error).message}`, true, "gi");
    },
  );

  const request = (supersede: boolean) => {
    stopRefining();
    const scene = sceneName();
    if (!scene) {
      img.hidden = true;
      showWaiting(null);
      info.textContent = "";
      return;
    }
    view.request({ x: store.state.x.slice(), scene, exposure: auto.checked ? "auto" : Number(exposure.value), tone: tone.value },
      store.state.movedAt || performance.now(), supersede);
  };
  sel.addEventListener("change", () => {
    fillViews();
    request(true);
  });
  camera.addEventListener("change", () => request(true));
  exposure.addEventListener("input", () => {
    auto.checked = false;
    showExposure(Number(exposure.value));
    request(false);
  });
  auto.addEventListener("change", () => request(false));
  tone.addEventListener("change", () => request(false));
  store.on(["x"], () => request(false));
  store.on(["dragging"], (st) => st.dragging && stopRefining());
  // The denoiser on or off (shared with the reference render's toggle): the same refinement (its
  // samples stay on the server), shown the other way.
  denoiseToggle.addEventListener("click", () => store.update({ denoise: !store.state.denoise }));
  store.on(["denoise"], (st) => {
    denoiseToggle.setAttribute("aria-pressed", String(st.denoise));
    denoiseToggle.classList.toggle("on", st.denoise);
    const shown = st.giShown;
    if (refining && shown && !st.dragging) {
      stopRefining();
      startRefining(shown);
    }
  });
  request(false);
}
