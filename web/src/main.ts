// The material browser page: loads the model, creates the typed store (state.ts) and the views
// (map card, reference render (preview), scene view (gi-view), real-time view, panels, point tools, path tool, scene pickers), which talk through it.
import "./style.css";
import { api } from "./api";
import { $ } from "./dom";
import { createMapPanel } from "./map-panel";
import { createGiView } from "./gi-view";
import { createGuidance } from "./guidance";
import { createLibrary } from "./library";
import { createPanels } from "./panels";
import { createPathTool } from "./path-tool";
import { createPointTools } from "./point-tools";
import { createPreview } from "./preview";
import { createRealtimeView } from "./realtime";
import { createScenePickers } from "./scene";
import { createSliders } from "./sliders";
import { createStore, moveTo, type PageStore } from "./state";
import { setStatus } from "./status";
import { keepUrl, readUrlView } from "./url-state";

async function main(): Promise<void> {
  const model = await api.model();
  $("model-info").textContent = `${model.name} · ${model.count} materials · q = ${model.dim}`;
  createGuidance();
  // A shared view (the address bar's hash) restores the point, scene, plane, view, layer and list.
  const restored = readUrlView(model);
  const env = restored.env ?? model.scenes.default_env, object = restored.object ?? model.scenes.default_object;
  let store: PageStore | null = null;
  const panel = createMapPanel(
    model,
    (x, dragging, t) => store && moveTo(store, x, dragging, t),
    () => store?.state ?? { env, object },
  );
  const { map } = panel;
  store = createStore(model, map, panel.layerTiming, env, object);
  createScenePickers(store);
  createPreview(store);
  createGiView(store);
  createPanels(store);
  createSliders(store, panel);
  createPointTools(store, map);
  createPathTool(store, map);
  createLibrary(store, map);

  const select = (id: string, value: string) => {
    const sel = $<HTMLSelectElement>(id);
    if (sel.value === value) return;
    sel.value = value;
    sel.dispatchEvent(new Event("change"));
  };
  if (restored.axes && model.dim > 2) {
    $<HTMLSelectElement>("axis-x").value = String(restored.axes[0]);
    $<HTMLSelectElement>("axis-y").value = String(restored.axes[1]);
    $("axis-x").dispatchEvent(new Event("change"));
  }
  if (restored.layer) select("layer", restored.layer);
  // Start at the shared point, else at the first material, so that the page opens on something real.
  const start = restored.x ?? model.latent[0].slice();
  map.setPoint(start);
  moveTo(store, start, false);
  if (restored.view) map.setViewState(restored.view);
  if (restored.list?.length) store.update({ shortlist: restored.list });
  panel.askLayer();
  keepUrl(store, map, () => $<HTMLSelectElement>("layer").value);
  void createRealtimeView(store);
}

main().catch((e) => {
  setStatus(`failed to load the model: ${(e as Error).message}`, true);
  $("model-info").textContent = "no model";
});
