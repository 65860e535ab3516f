// The tools of the current point: download it (for Mitsuba 3, pbrt-v4, MaterialX, glTF, Blender:
// downloads.ts) or its coordinates, upload a .binary
// file to project it onto the map, and fit sample files (fit-samples.ts; going to a material by
// name: library.ts).
import { api } from "./api";
import { $, download, fmtX } from "./dom";
import { createDownloadMenu } from "./downloads";
import { createFitSamples } from "./fit-samples";
import type { LatentMap } from "./map";
import { moveTo, type PageStore } from "./state";
import { setStatus } from "./status";

export function createPointTools(store: PageStore, map: LatentMap): void {
  const model = store.state.model;
  const goTo = (x: number[]) => {
    map.setPoint(x);
    moveTo(store, x, false);
  };
  createDownloadMenu(store);  // the table and the analytic fit, in five formats (downloads.ts)
  $("export-json").addEventListener("click", () => {
    const s = store.state;
    const body = { model: model.name, q: model.dim, x: s.x, weights: s.lastWeights?.top ?? [] };
    download(new Blob([JSON.stringify(body, null, 2)], { type: "application/json" }), "matlas-point.json");
  });

  const project = async (file: File) => {
    setStatus(`projecting ${file.name}…`);
    try {
      const reply = await api.project(file);
      store.update({ projected: { x: reply.x, residual: reply.residual } });
      map.projected = { x: reply.x, label: file.name.replace(/\.binary$/, "") };
      goTo(reply.x);
      setStatus(`${file.name}: x = (${fmtX(reply.x)}), relative residual ${reply.residual.toPrecision(3)}`);
    } catch (err) {
      setStatus(`upload: ${(err as Error).message}`, true, "upload");
    }
  };
  $<HTMLInputElement>("upload").addEventListener("change", async (e) => {
    const input = e.target as HTMLInputElement;
    const file = input.files?.[0];
    if (!file) return;
    try {
      await project(file);
    } finally {
      input.value = "";
    }
  });
  // Sparse samples (and files dropped on the map): fit-samples.ts.
  createFitSamples(store, map, project);
}
