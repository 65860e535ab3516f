// The page's typed state (one Store, web/src/store.ts), also exposed as window.matlas for the
// browser tests and for debugging in the console.
import type { FitSamplesReply, ModelInfo, WeightsReply } from "./api";
import type { LatentMap } from "./map";
import type { LayerTiming } from "./map-panel";
import { Store } from "./store";

/** An image shown in the preview: where, how large and in which scene. */
export interface ShownPreview {
  x: number[];
  size: number;
  env: string;
  object: string;
}

/** A material of the short list: a database material (index) or any point of the map. */
export interface ListItem {
  name: string;
  x: number[];
  index: number | null;
}

export interface PageState {
  model: ModelInfo;
  /** The current latent point. */
  x: number[];
  /** Whether the pointer is still down (the preview streams half-size images). */
  dragging: boolean;
  /** performance.now() of the event that moved the point (for the latency badge). */
  movedAt: number;
  env: string;
  object: string;
  /** The image now shown in the preview. */
  shown: ShownPreview | null;
  /** Every scene the preview showed, in order (the tests check no in-between combination). */
  shownScenes: string[];
  previews: number;
  latencies: number[];
  /** Whether the preview keeps refining while the pointer rests (POST /api/preview/refine). */
  refine: boolean;
  /** Whether the refined image is denoised (the server's dual-buffer filter: biased, labelled). */
  denoise: boolean;
  /** The refined image shown over the preview (null: none, the basis image shows). */
  refined: (ShownPreview & { spp: number; error: number | null; converged: boolean; denoised: boolean }) | null;
  refinedImages: number;
  /** While the server prepares the current scene: how long the page has been waiting for it. */
  preparing: { env: string; object: string; attempts: number; waitedMs: number } | null;
  /** The image shown in the scene view (GET /api/gi), and how many it has shown. */
  giShown: { x: number[]; scene: string; exposure: number | "auto"; tone: string } | null;
  giImages: number;
  /** The scene view's refinement at rest: the point, scene and samples of the refined image shown. */
  giRefined: { x: number[]; scene: string; spp: number; error: number | null; converged: boolean; denoised: boolean } | null;
  giRefinedImages: number;
  lastWeights: WeightsReply | null;
  projected: { x: number[]; residual: number } | null;
  /** The last sample file fitted on the map (fit-samples.ts). */
  fitted: { file: string; reply: FitSamplesReply } | null;
  /** The last measurement plan downloaded. */
  plan: { k: number; conditionedOn: number } | null;
  /** The short list (compared side by side, exported together). */
  shortlist: ListItem[];
  map: LatentMap;
  /** How the map's background layers arrive (map-panel.ts). */
  layerTiming: LayerTiming;
}

export type PageStore = Store<PageState>;

declare global {
  interface Window {
    matlas?: PageState;
  }
}

export function createStore(model: ModelInfo, map: LatentMap, layerTiming: LayerTiming, env: string, object: string): PageStore {
  const store = new Store<PageState>({
    model, x: map.point.slice(), dragging: false, movedAt: 0, env, object, shown: null, shownScenes: [],
    previews: 0, latencies: [], refine: true, denoise: true, refined: null, refinedImages: 0, preparing: null, giShown: null, giImages: 0,
    giRefined: null, giRefinedImages: 0,
    lastWeights: null, projected: null, fitted: null, plan: null, shortlist: [], map, layerTiming,
  });
  window.matlas = store.state;
  return store;
}

/** Moves the current point (the map is told separately when the move did not come from it). */
export function moveTo(store: PageStore, x: number[], dragging: boolean, at = performance.now()): void {
  store.update({ x: x.slice(), dragging, movedAt: at });
}

/** The database material at x (exactly its latent point), or null. */
export function materialAt(state: PageState, x: number[] = state.x): number | null {
  const i = state.model.latent.findIndex((p) => p.every((v, d) => Math.abs(v - x[d]) <= 1e-9 * (1 + Math.abs(v))));
  return i < 0 ? null : i;
}
