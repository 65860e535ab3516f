// The view in the address bar (its hash), so that a view can be shared and restored: the point,
// the scene, the map's plane, view and background layer, and the short list. Written (replaceState,
// no history entry) shortly after the page settles; read once at start.
import type { LatentMap } from "./map";
import type { ListItem, PageStore } from "./state";
import type { ModelInfo } from "./api";

export interface UrlView {
  x?: number[];
  env?: string;
  object?: string;
  axes?: [number, number];
  layer?: string;
  view?: { cx: number; cy: number; half: number };
  list?: ListItem[];
}

const nums = (s: string | null, n: number): number[] | undefined => {
  if (!s) return undefined;
  const v = s.split(",").map(Number);
  return v.length === n && v.every(Number.isFinite) ? v : undefined;
};

/** Reads the view from `hash` (#x=..&env=..), keeping only what is valid for `model`. */
export function readUrlView(model: ModelInfo, hash = location.hash): UrlView {
  const p = new URLSearchParams(hash.replace(/^#/, ""));
  const out: UrlView = {};
  const x = nums(p.get("x"), model.dim);
  if (x) out.x = x.map((v, d) => Math.min(model.domain.max[d], Math.max(model.domain.min[d], v)));
  const env = p.get("env"), object = p.get("object");
  if (env && model.scenes.envs.includes(env)) out.env = env;
  if (object && model.scenes.objects.includes(object)) out.object = object;
  const axes = nums(p.get("axes"), 2);
  if (axes && axes.every((a) => Number.isInteger(a) && a >= 0 && a < model.dim) && axes[0] !== axes[1]) {
    out.axes = [axes[0], axes[1]];
  }
  const layer = p.get("layer");
  if (layer && (layer === "none" || model.layers.includes(layer))) out.layer = layer;
  const view = nums(p.get("view"), 3);
  if (view && view[2] > 0) out.view = { cx: view[0], cy: view[1], half: view[2] };
  const list = p.get("list");
  if (list) {
    out.list = list.split(";").flatMap((tok): ListItem[] => {
      if (/^\d+$/.test(tok) && Number(tok) < model.count) {
        const i = Number(tok);
        return [{ name: model.names[i], x: model.latent[i].slice(), index: i }];
      }
      const v = nums(tok.replace(/_/g, ","), model.dim);
      return v ? [{ name: `point (${v.map((c) => c.toFixed(3)).join(", ")})`, x: v, index: null }] : [];
    });
  }
  return out;
}

/** The hash of the current view. */
export function urlOf(store: PageStore, map: LatentMap, layer: string): string {
  const s = store.state;
  const r = (v: number) => String(Number(v.toPrecision(7)));
  const p = new URLSearchParams();
  p.set("x", s.x.map(r).join(","));
  p.set("env", s.env);
  p.set("object", s.object);
  if (s.model.dim > 2) p.set("axes", map.axes.join(","));
  p.set("layer", layer);
  const v = map.viewState();
  p.set("view", [v.cx, v.cy, v.half].map(r).join(","));
  if (s.shortlist.length) {
    p.set("list", s.shortlist.map((it) => (it.index !== null ? String(it.index) : it.x.map(r).join("_"))).join(";"));
  }
  return "#" + p.toString().replace(/%2C/g, ",").replace(/%3B/g, ";");
}

/** Keeps the address bar's hash up to date (300 ms after the last change, not while dragging). */
export function keepUrl(store: PageStore, map: LatentMap, layer: () => string): void {
  let timer = 0;
  const write = () => {
    clearTimeout(timer);
    timer = window.setTimeout(() => {
      if (store.state.dragging) return write();
      const hash = urlOf(store, map, layer());
      if (hash !== location.hash) history.replaceState(null, "", hash);
    }, 300);
  };
  store.on(["x", "env", "object", "shortlist", "dragging"], write);
  map.viewListeners.push(write);
  for (const id of ["layer", "axis-x", "axis-y"]) document.getElementById(id)?.addEventListener("change", write);
  // A view pasted into the address bar of this tab (replaceState fires no hashchange): open it.
  window.addEventListener("hashchange", () => location.reload());
  write();
}
