// The scene view (docs/GI.md, docs/WEB.md): the material of the current point on an object of a
// path-traced scene (floor, box), composed by the server from a GI image basis (GET /api/gi)
// and updated while dragging: one request in flight, always for the newest point (latest.ts).
// Exposure is automatic by default (the scene's key with the mean material, one value for the
// whole map); moving the slider sets it by hand; the tone curve is filmic (ACES) by default.
// A scene is off until picked, unless the server was given its basis (then the first such scene
// is shown at once); while the server traces a picked scene (503), the view retries and shows the
// server's progress (retry.ts); picking another scene supersedes the request in flight.
import { api } from "./api";
import { $, fillSelect, showBlob } from "./dom";
import { LatestOnly } from "./latest";
import { retryWhileBusy, type Waiting } from "./retry";
import type { PageStore } from "./state";
import { clearError, setStatus } from "./status";

interface GiInput {
  x: number[];
  scene: string;
  exposure: number | "auto";
  tone: string;
}

export function createGiView(store: PageStore): void {
  const gi = store.state.model.gi;
  if (!gi || gi.scenes.length === 0) return;  // the server has no scenes: the view stays hidden
  $("gi-view").hidden = false;
  const sel = $<HTMLSelectElement>("gi-scene"), img = $<HTMLImageElement>("gi"), progress = $("gi-progress");
  const info = $("gi-info");
  const auto = $<HTMLInputElement>("gi-auto"), exposure = $<HTMLInputElement>("gi-exposure");
  const exposureValue = $("gi-exposure-value"), tone = $<HTMLSelectElement>("gi-tone");
  const showExposure = (stops: number) => {
    exposure.value = String(stops);
    exposureValue.textContent = `${stops >= 0 ? "+" : ""}${stops.toFixed(2)}`;
  };
  fillSelect(sel, [{ value: "", label: "off" }, ...gi.scenes.map((s) => ({ value: s, label: s }))], gi.preloaded[0] ?? "");

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
      if (sel.value !== input.scene) return;  // switched off meanwhile
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
    },
    (e) => {
      showWaiting(null);
      setStatus(`scene view: ${(e as Error).message}`, true, "gi");
    },
  );

  const request = (supersede: boolean) => {
    const scene = sel.value;
    if (!scene) {
      img.hidden = true;
      showWaiting(null);
      info.textContent = "";
      return;
    }
    view.request({ x: store.state.x.slice(), scene, exposure: auto.checked ? "auto" : Number(exposure.value), tone: tone.value },
      store.state.movedAt || performance.now(), supersede);
  };
  sel.addEventListener("change", () => request(true));
  exposure.addEventListener("input", () => {
    auto.checked = false;
    showExposure(Number(exposure.value));
    request(false);
  });
  auto.addEventListener("change", () => request(false));
  tone.addEventListener("change", () => request(false));
  store.on(["x"], () => request(false));
  request(false);
}
