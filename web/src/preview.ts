// The live preview: the server's image of the current point in the current scene. One request in
// flight, always the latest position (half-size while dragging, full size on release). While the
// server prepares a scene (503), the request is retried with backoff and the preview shows how
// long it has been waiting; a new scene supersedes (aborts) the request in flight, so only the
// scene last chosen is ever shown.
import { api } from "./api";
import { $, showBlob } from "./dom";
import { LatestOnly } from "./latest";
import { retryWhileBusy, type Waiting } from "./retry";
import type { PageStore, ShownPreview } from "./state";
import { clearError, setStatus } from "./status";

export function createPreview(store: PageStore): void {
  const img = $<HTMLImageElement>("preview");
  const progress = $("preview-progress");
  const { size: fullSize, drag_size: dragSize } = store.state.model.preview;

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
  store.on(["x"], (s) => preview.request(current(s.dragging ? dragSize : fullSize), s.movedAt));
  store.on(["env", "object"], () => preview.request(current(fullSize), performance.now(), true));
}
