// The panels of the current point: the largest weights with the variance and the plausibility
// line, the theta_h x theta_d slice, the lobe in the plane of incidence and the albedo curve.
import { api, type Plausibility } from "./api";
import { AlbedoChart, LobeChart, WeightsChart } from "./charts";
import { $, showBlob } from "./dom";
import { DragThrottle } from "./drag-throttle";
import { LatestOnly } from "./latest";
import { SlicePlot } from "./slice-plot";
import type { PageStore } from "./state";
import { clearError, setStatus } from "./status";

// While dragging, the panels follow at most every PANEL_DRAG_MS: their four requests and three
// chart redraws compete with the preview for the page's main thread (measured with
// bench/preview_latency.mjs: every 100 ms put the preview's p90 at 53 ms, every 300 ms at 34 ms).
const PANEL_DRAG_MS = 300;

export function createPanels(store: PageStore): void {
  const weightsChart = new WeightsChart($<HTMLCanvasElement>("weights-chart"));
  const lobeChart = new LobeChart($<HTMLCanvasElement>("lobe-chart"));
  const albedoChart = new AlbedoChart($<HTMLCanvasElement>("albedo-chart"));
  const phi = $<HTMLInputElement>("phi"), thetaI = $<HTMLInputElement>("theta-i");
  const slicePlot = new SlicePlot($<HTMLCanvasElement>("slice-plot"));
  const sliceImg = $<HTMLImageElement>("slice");
  // For the tests and the console: the panels' scales as last drawn.
  (window as unknown as { matlasPanels: unknown }).matlasPanels = { slice: slicePlot, lobe: lobeChart };

  const panels = new LatestOnly<number[], void>(
    async (x) => {
      const [w, slice, lobe, albedo] = await Promise.all([
        api.weights(x, 8), api.slice(x, Number(phi.value)), api.lobe(x, Number(thetaI.value)), api.albedo(x),
      ]);
      store.update({ lastWeights: w });
      weightsChart.update(w);
      $("variance").textContent = `variance ${w.variance.toFixed(3)}`;
      showPlausibility(w.plausibility);
      lobeChart.update(lobe);
      albedoChart.update(albedo);
      await showBlob(sliceImg, slice.blob);
      slicePlot.show(sliceImg, slice.max);
    },
    () => clearError("panels"),
    (e) => setStatus(`panels: ${(e as Error).message}`, true, "panels"),
  );

  const throttle = new DragThrottle<number[]>(PANEL_DRAG_MS, (x) => panels.request(x));
  store.on(["x"], (s) => throttle.request(s.x, s.dragging));

  phi.addEventListener("input", () => {
    $<HTMLOutputElement>("phi-out").value = phi.value;
    panels.request(store.state.x);
  });
  thetaI.addEventListener("input", () => {
    $<HTMLOutputElement>("ti-out").value = thetaI.value;
    panels.request(store.state.x);
  });
  $("lobe-log").addEventListener("change", (e) => {
    lobeChart.logScale = (e.target as HTMLInputElement).checked;
    lobeChart.update();
  });
}

/** The plausibility line under the weights: what is wrong with the current point, if anything. */
function showPlausibility(p: Plausibility): void {
  const el = $("plausibility");
  const problems: string[] = [];
  if (p.negative_fraction > 0) problems.push(`~${(100 * p.negative_fraction).toFixed(1)} % of values negative`);
  if (p.max_albedo > 1) problems.push(`albedo up to ${p.max_albedo.toFixed(2)} (reflects more light than it receives)`);
  if (p.min_albedo < 0) problems.push(`negative albedo (${p.min_albedo.toFixed(2)})`);
  el.classList.toggle("implausible", problems.length > 0);
  el.textContent = problems.length > 0
    ? `⚠ not physically plausible: ${problems.join("; ")}. Exports clamp negative values to 0.`
    : `physically plausible: albedo ${p.min_albedo.toFixed(2)}–${p.max_albedo.toFixed(2)}, no negative value among ${p.sampled_values} sampled`;
}
