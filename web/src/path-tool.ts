// The path tool: previews along the segment between two materials (or the current point), drawn
// on the map; a click on a preview goes there. Redrawn when the scene changes.
import { api } from "./api";
import { $, fillSelect, fmtX, showBlob } from "./dom";
import type { LatentMap } from "./map";
import { retryWhileBusy } from "./retry";
import { sceneReady } from "./scene-ready";
import { moveTo, type PageStore } from "./state";
import { setStatus } from "./status";

export function createPathTool(store: PageStore, map: LatentMap): void {
  const model = store.state.model;
  const pathA = $<HTMLSelectElement>("path-a"), pathB = $<HTMLSelectElement>("path-b");
  const pathItems = [{ value: "current", label: "current point" }, ...model.names.map((n, i) => ({ value: String(i), label: n }))];
  fillSelect(pathA, pathItems, "0");
  fillSelect(pathB, pathItems, String(Math.min(1, model.count - 1)));
  const pointOf = (v: string) => (v === "current" ? store.state.x.slice() : model.latent[Number(v)].slice());
  const nameOf = (v: string) => (v === "current" ? "current point" : model.names[Number(v)]);
  let run: AbortController | null = null;

  const showPath = async () => {
    const a = pointOf(pathA.value), b = pointOf(pathB.value);
    const steps = Math.max(2, Math.min(16, Number($<HTMLInputElement>("path-steps").value) || 8));
    // The ends are the exact points (a rounded endpoint would miss a material's exact weights).
    const samples = Array.from({ length: steps }, (_, k) =>
      k === steps - 1 ? b.slice() : a.map((v, d) => v + ((b[d] - v) * k) / (steps - 1)));
    map.path = { a, b, samples };
    map.redraw();
    run?.abort();
    const signal = (run = new AbortController()).signal;
    const strip = $("strip");
    strip.replaceChildren(
      ...samples.map((x, k) => {
        const btn = document.createElement("button");
        btn.type = "button";
        btn.className = "strip-item";
        btn.title = `t = ${(k / (steps - 1)).toFixed(2)}: x = (${fmtX(x)})`;
        btn.addEventListener("click", () => {
          map.setPoint(x);
          moveTo(store, x, false);
        });
        const img = document.createElement("img");
        img.alt = btn.title;
        // Its caption: where along the segment, and the ends' names.
        const caption = document.createElement("span");
        caption.className = "caption";
        const t = (k / (steps - 1)).toFixed(2);
        const end = k === 0 ? nameOf(pathA.value) : k === steps - 1 ? nameOf(pathB.value) : "";
        caption.textContent = `t = ${t}`;
        if (end) {
          const b = document.createElement("b");
          b.textContent = ` ${end}`;
          caption.append(b);
          caption.title = end;
        }
        btn.append(img, caption);
        return btn;
      }),
    );
    const imgs = strip.querySelectorAll("img");
    const { env, object } = store.state;
    try {
      await sceneReady(env, object, signal);
      for (let k = 0; k < samples.length && !signal.aborted; k++) {
        const blob = await retryWhileBusy((s) => api.preview(samples[k], env, object, 96, s), { signal });
        if (!signal.aborted) await showBlob(imgs[k], blob);
      }
    } catch (e) {
      if (!signal.aborted) setStatus(`path: ${(e as Error).message}`, true, "path");
    }
  };
  const go = () => void showPath();
  $("path-go").addEventListener("click", go);
  $("path-clear").addEventListener("click", () => {
    run?.abort();
    map.path = null;
    map.redraw();
    $("strip").replaceChildren();
  });
  store.on(["env", "object"], () => {
    if (map.path) go();
  });
}
