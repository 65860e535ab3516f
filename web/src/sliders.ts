// For q > 2: the choice of the map's plane (its two axes) and sliders for the other coordinates;
// and the coordinates line under the preview.
import { $, fillSelect, fmtX } from "./dom";
import type { MapPanel } from "./map-panel";
import { moveTo, type PageStore } from "./state";

export function createSliders(store: PageStore, { map, refreshLayer }: MapPanel): void {
  const model = store.state.model;
  const sliders = $("sliders");
  const sync = () => {
    const x = store.state.x;
    $("coords").textContent = `x = (${fmtX(x)})`;
    sliders.querySelectorAll<HTMLInputElement>("input[type=range]").forEach((s) => {
      const d = Number(s.dataset.dim);
      s.value = String(x[d]);
      (s.nextElementSibling as HTMLOutputElement).value = x[d].toFixed(3);
    });
  };
  const build = () => {
    sliders.replaceChildren();
    for (let d = 0; d < model.dim; d++) {
      if (map.axes.includes(d)) continue;
      const label = document.createElement("label");
      label.className = "slider";
      const s = document.createElement("input");
      s.type = "range";
      s.min = String(model.domain.min[d]);
      s.max = String(model.domain.max[d]);
      s.step = String((model.domain.max[d] - model.domain.min[d]) / 500);
      s.value = String(store.state.x[d]);
      s.dataset.dim = String(d);
      s.setAttribute("aria-label", `latent coordinate ${d + 1}`);
      const out = document.createElement("output");
      s.addEventListener("input", (e) => {
        const x = store.state.x.slice();
        x[d] = Number(s.value);
        map.setPoint(x);
        moveTo(store, x, true, e.timeStamp);
        refreshLayer();
      });
      s.addEventListener("change", () => moveTo(store, store.state.x, false));
      label.append(`x${d + 1} `, s, out);
      sliders.append(label);
    }
    sync();
  };
  store.on(["x"], sync);
  if (model.dim > 2) {
    $("axes-controls").hidden = false;
    const axisItems = model.latent[0].map((_, d) => ({ value: String(d), label: `x${d + 1}` }));
    const ax = $<HTMLSelectElement>("axis-x"), ay = $<HTMLSelectElement>("axis-y");
    fillSelect(ax, axisItems, "0");
    fillSelect(ay, axisItems, "1");
    const onAxes = () => {
      const a = Number(ax.value);
      let b = Number(ay.value);
      if (a === b) b = (a + 1) % model.dim;
      ay.value = String(b);
      map.setAxes([a, b]);
      build();
    };
    ax.addEventListener("change", onAxes);
    ay.addEventListener("change", onAxes);
  }
  build();
}
