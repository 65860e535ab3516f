// The material browser page: loads the model, creates the typed store (state.ts) and the views
// (map card, reference render (preview), scene view (gi-view), real-time view, panels, point tools, path tool, scene pickers), which talk through it.
import "./style.css";
import { api } from "./api";
import { $ } from "./dom";
import { createMapPanel } from "./map-panel";
import { createGiView } from "./gi-view";
import { createPanels } from "./panels";
import { createPathTool } from "./path-tool";
import { createPointTools } from "./point-tools";
import { createPreview } from "./preview";
import { createRealtimeView } from "./realtime";
import { createScenePickers } from "./scene";
import { createSliders } from "./sliders";
import { createStore, moveTo, type PageStore } from "./state";
import { setStatus } from "./status";

async function main(): Promise<void> {
  const model = await api.model();
  $("model-info").textContent = `${model.name} · ${model.count} materials · q = ${model.dim}`;
  const { default_env: env, default_object: object } = model.scenes;
  let store: PageStore | null = null;
  const panel = createMapPanel(
    model,
    (x, dragging, t) => store && moveTo(store, x, dragging, t),
    () => store?.state ?? { env, object },
  );
  const { map } = panel;
  store = createStore(model, map, env, object);
  createScenePickers(store);
  createPreview(store);
  createGiView(store);
  createPanels(store);
  createSliders(store, panel);
  createPointTools(store, map);
  createPathTool(store, map);

  // Start at the first material so that the page opens on something real.
  const start = model.latent[0].slice();
  map.setPoint(start);
  moveTo(store, start, false);
  panel.refreshLayer();
  createRealtimeView(store).catch((e) => setStatus(`real-time view: ${(e as Error).message}`, true, "realtime"));
}

main().catch((e) => {
  setStatus(`failed to load the model: ${(e as Error).message}`, true);
  $("model-info").textContent = "no model";
});
