// The map card: the latent map with its hover tooltip, the background layer over the visible
// rectangle, the legend and label count, the toolbar (layer, labels, fit, crowd) and the
// interpolation badge.
import { api, type MapRequest, type ModelInfo } from "./api";
import { $ } from "./dom";
import { LatestOnly } from "./latest";
import { LatentMap, type ViewRect } from "./map";
import { LABEL_ALPHA } from "./map-draw";
import { setStatus } from "./status";

/** A background layer, or none. */
type MapKind = NonNullable<MapRequest["layer"]> | "none";

export interface MapPanel {
  map: LatentMap;
  /** Asks for the background layer of the current view, after `delayMs` (default 120: debounced). */
  refreshLayer(delayMs?: number): void;
  /** Asks for the layer now, without a timer (the page's first: a timer waited 0.3 s for the
   *  browser to lay out a 1000-tile library). */
  askLayer(): void;
  layerTiming: LayerTiming;
}

/**
 * Layers that take long to compute (many materials: each cell solves its convex weights) come in
 * two steps: a coarse one, shown as soon as it arrives, then the full one over it. A layer's time
 * grows about linearly with its width at a given aspect, not with its cells (each cell's convex
 * solve starts from its neighbour's, and the work is in the changes of the solution along the
 * rows: the plausibility layer 16, 32, 64 and 128 cells wide took 0.07, 0.13, 0.27 and 0.79 s
 * at n = 1000, docs/BENCHMARKS.md "Map layers"), so the coarse layer's width is the full one's
 * scaled to arrive in COARSE_TARGET_MS.
 */
export interface LayerTiming {
  /** A coarse layer first when the last full layer took longer than this. */
  coarseAfterMs: number;
  /** How long the last full layer of each kind took. A kind not yet shown goes by the others
   *  (expectedLayerMs); with none yet, models of more than COARSE_FIRST_COUNT materials start
   *  coarse. Kinds differ (the variance layer projects nothing, about twice as fast as the
   *  others at n = 1000). */
  lastMs: Partial<Record<string, number>>;
  /** Coarse layers shown so far. */
  coarseShown: number;
  /** Whether a layer is on its way: the refinements at rest wait meanwhile (waitForLayer). */
  loading: boolean;
}

/**
 * Resolves once no map layer is on its way (or `signal` aborts): the refinement loops of the
 * preview and the scene view wait here before each pass, so that a layer the user asked for gets
 * the server's cores (on 2 cores a layer at n = 1000 took twice as long beside them).
 */
export async function waitForLayer(timing: LayerTiming, signal: AbortSignal): Promise<void> {
  while (timing.loading && !signal.aborted) await new Promise((resolve) => setTimeout(resolve, 50));
}

/**
 * Resolves once no map layer has been on its way for `quietMs`: work that the page can start
 * later (the real-time card's coefficients: 60 MB at n = 1000, decoded and uploaded by the
 * browser on the same cores as a local server) waits here, so that the first layers arrive first.
 */
export async function waitForQuietMap(timing: LayerTiming, quietMs: number): Promise<void> {
  let quietSince = performance.now();
  for (;;) {
    const now = performance.now();
    if (timing.loading) quietSince = now;
    else if (now - quietSince >= quietMs) return;
    await new Promise((resolve) => setTimeout(resolve, 50));
  }
}

/** From this many materials the first layer is coarse first (128^2 cells: seconds at n = 1000). */
const COARSE_FIRST_COUNT = 300;
/** Cells per row of a full layer; the coarse one's at most and at least, and its time. */
const LAYER_COLS = 128, COARSE_MAX_COLS = 64, COARSE_MIN_COLS = 12, COARSE_TARGET_MS = 500;

/**
 * The time to expect of a full layer of `kind`: its own last one; before it has one, the slowest
 * last layer of the other kinds (the variance layer's only for a variance layer: it projects
 * nothing and takes about half the others' time); none yet: undefined.
 */
export function expectedLayerMs(kind: string, lastMs: Partial<Record<string, number>>): number | undefined {
  const own = lastMs[kind];
  if (own !== undefined) return own;
  const others = Object.entries(lastMs)
    .filter(([k, ms]) => ms !== undefined && (kind === "variance" || k !== "variance"))
    .map(([, ms]) => ms as number);
  return others.length > 0 ? Math.max(...others) : undefined;
}

/** The width of the coarse layer after a full one of its kind that took `lastMs` (none yet: undefined). */
export function coarseColumns(lastMs: number | undefined): number {
  if (lastMs === undefined || !(lastMs > 0)) return 24;
  const cols = Math.round((LAYER_COLS * COARSE_TARGET_MS) / lastMs);
  return Math.max(COARSE_MIN_COLS, Math.min(COARSE_MAX_COLS, cols));
}

export function createMapPanel(
  model: ModelInfo,
  move: (x: number[], dragging: boolean, eventTime: number) => void,
  scene: () => { env: string; object: string },
): MapPanel {
  showInterpolation(model.interpolation ?? "gp");
  const tooltip = $("tooltip");
  const thumb = tooltip.querySelector("img")!;
  thumb.addEventListener("error", () => {
    // The chosen scene is still being prepared (503): the default scene's thumbnail meanwhile.
    const { default_env, default_object } = model.scenes;
    const fallback = api.thumbnailUrl(Number(thumb.dataset.index), default_env, default_object);
    if (thumb.getAttribute("src") !== fallback) thumb.src = fallback;
  });
  const layerSel = $<HTMLSelectElement>("layer");
  // While a layer is requested the map keeps showing the previous one (over its own rectangle)
  // and says that a new one is coming; a newer view aborts the request in flight.
  const mapWrap = $("map-wrap");
  const layerTiming: LayerTiming = { coarseAfterMs: 1200, lastMs: {}, coarseShown: 0, loading: false };
  // What a point far from the data is depends on the interpolation: the GP's weights fall to zero
  // (the database mean), convex weights still sum to 1 (a mix of the nearest materials). The layers
  // that fade there (transparent cells, drawn over the "no data here" hatching): the albedo layer,
  // and the plausibility layer of convex weights.
  const convex = (model.interpolation ?? "gp") === "convex";
  const hatched = (kind: MapKind) => kind === "albedo" || (kind === "plausibility" && convex);
  const loading = (on: boolean) => {
    layerTiming.loading = on;
    mapWrap.classList.toggle("layer-loading", on);
    mapWrap.setAttribute("aria-busy", String(on));
  };
  let layerTimer = 0;
  const layer = new LatestOnly<{ view: ViewRect; kind: MapKind; axes: [number, number]; x: number[] }, ImageBitmap | null>(
    async ({ view, kind, axes, x }, signal) => {
      if (kind === "none") return null;
      const rowsOf = (cols: number) =>
        Math.max(4, Math.min(256, Math.round((cols * (view.y1 - view.y0)) / (view.x1 - view.x0))));
      const rect: MapRequest["rect"] = [view.x0, view.x1, view.y0, view.y1];
      const last = expectedLayerMs(kind, layerTiming.lastMs);
      const slow = last === undefined ? model.count > COARSE_FIRST_COUNT : last > layerTiming.coarseAfterMs;
      if (slow) {
        const cols = coarseColumns(last);
        const coarse = await api.map({ layer: kind, axes, x, rect, size: [cols, rowsOf(cols)] }, signal);
        const bitmap = await createImageBitmap(coarse);
        if (!signal.aborted) {
          map.setLayer(bitmap, view, hatched(kind));
          layerTiming.coarseShown += 1;
        }
      }
      const started = performance.now();
      const blob = await api.map({ layer: kind, axes, x, rect, size: [LAYER_COLS, rowsOf(LAYER_COLS)] }, signal);
      layerTiming.lastMs[kind] = performance.now() - started;
      return createImageBitmap(blob);
    },
    (bitmap, input) => map.setLayer(bitmap, input.view, hatched(input.kind)),
    (e) => setStatus(`map layer: ${(e as Error).message}`, true, "map layer"),
    () => loading(false),
  );
  // Debounced for views (a pan or zoom sends many); at once for a change of layer (delay 0: after
  // the handlers of the same event, so that a restored layer and view ask once).
  const askLayer = () => {
    clearTimeout(layerTimer);
    const kind = layerSel.value as MapKind;
    loading(kind !== "none");
    layer.request({ view: map.view, kind, axes: map.axes, x: map.point.slice() }, performance.now(), true);
  };
  const refreshLayer = (delayMs = 120) => {
    clearTimeout(layerTimer);
    layerTimer = window.setTimeout(askLayer, delayMs);
  };

  const map = new LatentMap(
    $<HTMLCanvasElement>("map"), model.latent, model.names, model.colors, model.domain, model.bounds,
    {
      move,
      hover: (i, cx, cy) => {
        if (i === null) {
          tooltip.hidden = true;
          return;
        }
        const { env, object } = scene();
        const key = `${i}/${env}/${object}`;
        if (thumb.dataset.key !== key) {
          thumb.dataset.key = key;
          thumb.dataset.index = String(i);
          thumb.src = api.thumbnailUrl(i, env, object);
        }
        tooltip.querySelector(".name")!.textContent = model.names[i];
        const wrap = tooltip.parentElement!.getBoundingClientRect();
        tooltip.style.left = `${Math.min(cx - wrap.left + 14, wrap.width - 140)}px`;
        tooltip.style.top = `${Math.min(cy - wrap.top + 14, wrap.height - 150)}px`;
        tooltip.hidden = false;
      },
      viewChanged: () => refreshLayer(),
    },
  );

  const fade = model.uncertainty ?? { fade_from: 0.5, fade_to: 0.9 };
  const far = convex
    ? "a point there is a mix of the nearest materials (see Largest weights), not a measured one"
    : "the model only has the database mean there";
  const showLegend = () => {
    const kind = layerSel.value as MapKind;
    const item = (swatch: string, text: string) => `<span class="item"><span class="swatch ${swatch}"></span>${text}</span>`;
    // What the layer's colours mean, then, for the layers that fade, what the hatching means.
    const meaning =
      kind === "albedo"
        ? item("fade", `albedo fades out from variance ${fade.fade_from}`)
        : kind === "variance"
          ? item("variance", "predictive variance 0 (at the data) → 1 (far away)")
          : kind === "plausibility" && model.plausible_everywhere
            ? item("fade", `every point is plausible (a convex mix of plausible materials): dimmed albedo, fading out from variance ${fade.fade_from}`)
            : kind === "plausibility"
              ? item("red", "not physically plausible (negative values or albedo outside [0, 1])")
              : "";
    $("legend-layer").innerHTML =
      meaning + (hatched(kind) ? item("hatch", `no data here (variance &gt; ${fade.fade_to}): ${far}`) : "");
  };
  if (model.dim > 2) {
    $("legend-far").textContent =
      `q = ${model.dim}: points fade with their distance from the displayed slice (the other coordinates); faded points are not labelled`;
  }
  showLegend();
  let labelText = "";
  map.onDrawn = () => {
    const shown = map.labelBoxes.length, n = map.visibleMaterials;
    const far = model.dim > 2 ? map.markerAlpha.filter((a) => a < LABEL_ALPHA).length : 0;
    const text = !map.showLabels || shown >= n ? ""
      : `${shown} of ${n} labels shown: ${far > 0 ? `${far} far from the slice, ` : ""}hover a point or zoom in for the others`;
    if (text !== labelText) $("label-count").textContent = labelText = text;
  };

  layerSel.addEventListener("change", () => {
    if (layerSel.value === "none") map.setLayer(null, map.view);
    showLegend();
    refreshLayer(0);
  });
  $<HTMLInputElement>("labels").addEventListener("change", (e) => {
    map.showLabels = (e.target as HTMLInputElement).checked;
    map.redraw();
  });
  $("reset-view").addEventListener("click", () => map.resetView(true));
  $("core-view").addEventListener("click", () => map.resetView(true, true));
  return { map, refreshLayer, askLayer, layerTiming };
}

/** The interpolation mode badge next to the map, with what the mode means. */
function showInterpolation(mode: string): void {
  const el = $("interpolation");
  el.textContent = `interpolation: ${mode === "convex" ? "convex" : mode === "gp" ? "GP (paper)" : mode}`;
  el.classList.add(mode === "convex" ? "convex" : "gp");
  el.dataset.mode = mode;
  el.title = mode === "convex"
    ? "Convex interpolation: every point of the map is a mix of database materials with non-negative weights " +
      "summing to 1, so its table has no negative value and its albedo never exceeds the largest of the inputs."
    : mode === "gp"
      ? "GP interpolation (Soler et al. 2018): the weights K⁻¹k(x) can be negative or sum above 1, so points between " +
        "very different materials can have negative values or reflect more light than they receive " +
        "(see the plausibility line and the plausibility background)."
      : `interpolation mode "${mode}"`;
}
