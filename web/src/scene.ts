// The scene pickers (environment, object) in the top bar. A change is committed to the store
// SCENE_SETTLE_MS after the last one, both fields in one update: switching environment and object
// together asks the server for that one combination, never for the one in between.
import { $, fillSelect } from "./dom";
import type { PageStore } from "./state";

const SCENE_SETTLE_MS = 250;

export function createScenePickers(store: PageStore): void {
  const { scenes } = store.state.model;
  const envSel = $<HTMLSelectElement>("env"), objSel = $<HTMLSelectElement>("object");
  fillSelect(envSel, scenes.envs.map((e) => ({ value: e, label: e })), store.state.env);
  fillSelect(objSel, scenes.objects.map((o) => ({ value: o, label: o })), store.state.object);
  let timer = 0;
  const onChange = () => {
    clearTimeout(timer);
    timer = window.setTimeout(() => {
      const { env, object } = store.state;
      if (envSel.value !== env || objSel.value !== object) store.update({ env: envSel.value, object: objSel.value });
    }, SCENE_SETTLE_MS);
  };
  envSel.addEventListener("change", onChange);
  objSel.addEventListener("change", onChange);
}
