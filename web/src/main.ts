// The material browser page: wires the latent map, the live preview, the panels, the path tool,
// export and upload to the matlas API.
import "./style.css";
import { api, type ModelInfo, type Plausibility, type WeightsReply } from "./api";
import { AlbedoChart, LobeChart, WeightsChart } from "./charts";
import { LatestOnly } from "./latest";
import { LatentMap, type ViewRect } from "./map";

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

/** State exposed for the browser tests and for debugging in the console. */
interface PageState {
  model: ModelInfo;
  x: number[];
  env: string;
  object: string;
  /** x of the image now shown in the preview, and its size. */
  shown: { x: number[]; size: number } | null;
  previews: number;
  latencies: number[];
  lastWeights: WeightsReply | null;
  projected: { x: number[]; residual: number } | null;
  map: LatentMap;
}
declare global {
  interface Window {
    matlas?: PageState;
  }
}

function fmtX(x: number[]): string {
  return x.map((v) => v.toFixed(4)).join(", ");
}

function setStatus(text: string, error = false): void {
  const s = $("status");
  s.textContent = text;
  s.classList.toggle("error", error);
}

function download(blob: Blob, name: string): void {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

function fillSelect(sel: HTMLSelectElement, items: { value: string; label: string }[], value?: string): void {
  sel.replaceChildren(...items.map((it) => new Option(it.label, it.value)));
  if (value !== undefined) sel.value = value;
}

async function showBlob(img: HTMLImageElement, blob: Blob): Promise<void> {
  const url = URL.createObjectURL(blob);
  const old = img.src;
  img.src = url;
  try {
    await img.decode();
  } catch {
    /* a replaced image aborts decode(); the newer one is already on its way */
  }
  if (old.startsWith("blob:")) URL.revokeObjectURL(old);
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

async function main(): Promise<void> {
  const model = await api.model();
  $("model-info").textContent = `${model.name} · ${model.count} materials · q = ${model.dim}`;
  showInterpolation(model.interpolation ?? "gp");
  const fade = model.uncertainty ?? { fade_from: 0.5, fade_to: 0.9 };

  const envSel = $<HTMLSelectElement>("env"), objSel = $<HTMLSelectElement>("object");
  fillSelect(envSel, model.scenes.envs.map((e) => ({ value: e, label: e })), model.scenes.default_env);
  fillSelect(objSel, model.scenes.objects.map((o) => ({ value: o, label: o })), model.scenes.default_object);

  const previewImg = $<HTMLImageElement>("preview");
  const tooltip = $("tooltip");
  const weightsChart = new WeightsChart($<HTMLCanvasElement>("weights-chart"));
  const lobeChart = new LobeChart($<HTMLCanvasElement>("lobe-chart"));
  const albedoChart = new AlbedoChart($<HTMLCanvasElement>("albedo-chart"));

  // --- live preview: one request in flight, always the latest position ---
  const preview = new LatestOnly<{ x: number[]; size: number }, Blob>(
    ({ x, size }) => api.preview(x, state.env, state.object, size),
    async (blob, input, startedAt) => {
      await showBlob(previewImg, blob);
      state.shown = { x: input.x, size: input.size };
      state.previews++;
      const ms = performance.now() - startedAt;
      state.latencies.push(ms);
      if (state.latencies.length > 500) state.latencies.shift();
      const recent = state.latencies.slice(-30).sort((a, b) => a - b);
      $("latency").textContent = `${Math.round(ms)} ms · median ${Math.round(recent[recent.length >> 1])} ms`;
      previewImg.dataset.x = JSON.stringify(input.x);
      previewImg.dataset.size = String(input.size);
    },
    (e) => setStatus(`preview: ${(e as Error).message}`, true),
  );

  // --- panels: weights, slice, lobe, albedo for the latest point ---
  const panels = new LatestOnly<number[], void>(
    async (x) => {
      const [w, slice, lobe, albedo] = await Promise.all([
        api.weights(x, 8),
        api.slice(x, Number($<HTMLInputElement>("phi").value)),
        api.lobe(x, Number($<HTMLInputElement>("theta-i").value)),
        api.albedo(x),
      ]);
      state.lastWeights = w;
      weightsChart.update(w);
      $("variance").textContent = `variance ${w.variance.toFixed(3)}`;
      showPlausibility(w.plausibility);
      lobeChart.update(lobe);
      albedoChart.update(albedo);
      await showBlob($<HTMLImageElement>("slice"), slice);
    },
    () => {},
    (e) => setStatus(`panels: ${(e as Error).message}`, true),
  );

  // --- background layer over the visible rectangle (debounced) ---
  let layerTimer = 0;
  const layer = new LatestOnly<{ view: ViewRect; kind: string; axes: [number, number]; x: number[] }, ImageBitmap | null>(
    async ({ view, kind, axes, x }) => {
      if (kind === "none") return null;
      const rows = Math.max(4, Math.min(256, Math.round((128 * (view.y1 - view.y0)) / (view.x1 - view.x0))));
      const blob = await api.map({ layer: kind, axes, x, rect: [view.x0, view.x1, view.y0, view.y1], size: [128, rows] });
      return createImageBitmap(blob);
    },
    (bitmap, input) => state.map.setLayer(bitmap, input.view, input.kind === "albedo"),
    (e) => setStatus(`map layer: ${(e as Error).message}`, true),
  );
  const refreshLayer = () => {
    clearTimeout(layerTimer);
    layerTimer = window.setTimeout(() => {
      const m = state.map;
      layer.request({ view: m.view, kind: $<HTMLSelectElement>("layer").value, axes: m.axes, x: m.point.slice() });
    }, 120);
  };

  const fullSize = model.preview.size, dragSize = model.preview.drag_size;
  // While dragging, the panels follow at most every PANEL_DRAG_MS: their four requests and three
  // chart redraws compete with the preview for the page's main thread (measured with
  // bench/preview_latency.mjs: every 100 ms put the preview's p90 at 53 ms, every 300 ms at 34 ms).
  const PANEL_DRAG_MS = 300;
  let lastPanels = 0, panelTimer = 0;
  const moveTo = (x: number[], dragging: boolean, t = performance.now()) => {
    state.x = x.slice();
    $("coords").textContent = `x = (${fmtX(x)})`;
    preview.request({ x: state.x, size: dragging ? dragSize : fullSize }, t);
    clearTimeout(panelTimer);
    const now = performance.now();
    if (!dragging || now - lastPanels > PANEL_DRAG_MS) {
      lastPanels = now;
      panels.request(state.x);
    } else {
      panelTimer = window.setTimeout(() => {
        lastPanels = performance.now();
        panels.request(state.x);
      }, PANEL_DRAG_MS);
    }
    syncSliders();
  };

  const map = new LatentMap(
    $<HTMLCanvasElement>("map"), model.latent, model.names, model.colors, model.domain, model.bounds,
    {
      move: moveTo,
      hover: (i, cx, cy) => {
        if (i === null) {
          tooltip.hidden = true;
          return;
        }
        const img = tooltip.querySelector("img")!;
        const url = api.thumbnailUrl(i, state.env, state.object);
        if (img.getAttribute("src") !== url) img.src = url;
        tooltip.querySelector(".name")!.textContent = model.names[i];
        const wrap = tooltip.parentElement!.getBoundingClientRect();
        tooltip.style.left = `${Math.min(cx - wrap.left + 14, wrap.width - 140)}px`;
        tooltip.style.top = `${Math.min(cy - wrap.top + 14, wrap.height - 150)}px`;
        tooltip.hidden = false;
      },
      viewChanged: refreshLayer,
    },
  );

  const state: PageState = {
    model, x: map.point.slice(), env: envSel.value, object: objSel.value, shown: null, previews: 0,
    latencies: [], lastWeights: null, projected: null, map,
  };
  window.matlas = state;

  // --- plane choice and sliders for the other coordinates (q > 2) ---
  const sliders = $("sliders");
  const syncSliders = () => {
    sliders.querySelectorAll<HTMLInputElement>("input[type=range]").forEach((s) => {
      const d = Number(s.dataset.dim);
      s.value = String(state.x[d]);
      (s.nextElementSibling as HTMLOutputElement).value = state.x[d].toFixed(3);
    });
  };
  const buildSliders = () => {
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
      s.value = String(state.x[d]);
      s.dataset.dim = String(d);
      s.setAttribute("aria-label", `latent coordinate ${d + 1}`);
      const out = document.createElement("output");
      s.addEventListener("input", (e) => {
        const x = state.x.slice();
        x[d] = Number(s.value);
        map.setPoint(x);
        moveTo(x, true, e.timeStamp);
        refreshLayer();
      });
      s.addEventListener("change", () => moveTo(state.x, false));
      label.append(`x${d + 1} `, s, out);
      sliders.append(label);
    }
    syncSliders();
  };
  if (model.dim > 2) {
    $("axes-controls").hidden = false;
    const axisItems = model.latent[0].map((_, d) => ({ value: String(d), label: `x${d + 1}` }));
    const ax = $<HTMLSelectElement>("axis-x"), ay = $<HTMLSelectElement>("axis-y");
    fillSelect(ax, axisItems, "0");
    fillSelect(ay, axisItems, "1");
    const onAxes = () => {
      let a = Number(ax.value), b = Number(ay.value);
      if (a === b) b = (a + 1) % model.dim;
      ay.value = String(b);
      map.setAxes([a, b]);
      buildSliders();
    };
    ax.addEventListener("change", onAxes);
    ay.addEventListener("change", onAxes);
  }
  buildSliders();

  // --- legend: what the background means, and how many labels are shown ---
  const showLegend = () => {
    const kind = $<HTMLSelectElement>("layer").value;
    const el = $("legend-layer");
    const item = (swatch: string, text: string) => `<span class="item"><span class="swatch ${swatch}"></span>${text}</span>`;
    el.innerHTML =
      kind === "albedo"
        ? item("fade", `albedo fades out from variance ${fade.fade_from}`) +
          item("hatch", `no data here (variance &gt; ${fade.fade_to}): the model only has the database mean`)
        : kind === "variance"
          ? item("variance", "predictive variance 0 (at the data) → 1 (far away)")
          : kind === "plausibility"
            ? item("red", "not physically plausible (negative values or albedo outside [0, 1])")
            : "";
  };
  showLegend();
  let labelText = "";
  map.onDrawn = () => {
    const shown = map.labelBoxes.length, n = map.visibleMaterials;
    const text = !map.showLabels ? "" : shown < n ? `${shown} of ${n} labels shown: hover a point or zoom in for the others` : "";
    if (text !== labelText) $("label-count").textContent = labelText = text;
  };

  // --- toolbar ---
  $("layer").addEventListener("change", () => {
    if ($<HTMLSelectElement>("layer").value === "none") map.setLayer(null, map.view);
    showLegend();
    refreshLayer();
  });
  $<HTMLInputElement>("labels").addEventListener("change", (e) => {
    map.showLabels = (e.target as HTMLInputElement).checked;
    map.redraw();
  });
  $("reset-view").addEventListener("click", () => map.resetView(true));
  $("core-view").addEventListener("click", () => map.resetView(true, true));
  const onScene = () => {
    state.env = envSel.value;
    state.object = objSel.value;
    preview.request({ x: state.x, size: fullSize });
    if (map.path) void showPath();
  };
  envSel.addEventListener("change", onScene);
  objSel.addEventListener("change", onScene);

  // --- panel controls ---
  $("phi").addEventListener("input", () => {
    $<HTMLOutputElement>("phi-out").value = $<HTMLInputElement>("phi").value;
    panels.request(state.x);
  });
  $("theta-i").addEventListener("input", () => {
    $<HTMLOutputElement>("ti-out").value = $<HTMLInputElement>("theta-i").value;
    panels.request(state.x);
  });
  $("lobe-log").addEventListener("change", (e) => {
    lobeChart.logScale = (e.target as HTMLInputElement).checked;
    lobeChart.update();
  });

  // --- materials ---
  const materialItems = model.names.map((n, i) => ({ value: String(i), label: n }));
  const matSel = $<HTMLSelectElement>("material");
  fillSelect(matSel, [{ value: "", label: "—" }, ...materialItems], "");
  matSel.addEventListener("change", () => {
    if (matSel.value === "") return;
    const x = model.latent[Number(matSel.value)].slice();
    map.setPoint(x);
    moveTo(x, false);
  });

  // --- export ---
  $("export-binary").addEventListener("click", async () => {
    try {
      setStatus("computing the table…");
      const x = state.x.slice();
      const blob = await api.exportMerl(x);
      download(blob, `matlas-${x.map((v) => v.toFixed(3)).join("_")}.binary`);
      setStatus(`downloaded the MERL table at (${fmtX(x)})`);
    } catch (e) {
      setStatus(`export: ${(e as Error).message}`, true);
    }
  });
  $("export-json").addEventListener("click", () => {
    const body = { model: model.name, q: model.dim, x: state.x, weights: state.lastWeights?.top ?? [] };
    download(new Blob([JSON.stringify(body, null, 2)], { type: "application/json" }), "matlas-point.json");
  });

  // --- upload and projection ---
  $<HTMLInputElement>("upload").addEventListener("change", async (e) => {
    const input = e.target as HTMLInputElement;
    const file = input.files?.[0];
    if (!file) return;
    setStatus(`projecting ${file.name}…`);
    try {
      const reply = await api.project(file);
      state.projected = { x: reply.x, residual: reply.residual };
      map.projected = { x: reply.x, label: file.name.replace(/\.binary$/, "") };
      map.setPoint(reply.x);
      moveTo(reply.x, false);
      setStatus(`${file.name}: x = (${fmtX(reply.x)}), relative residual ${reply.residual.toPrecision(3)}`);
    } catch (err) {
      setStatus(`upload: ${(err as Error).message}`, true);
    } finally {
      input.value = "";
    }
  });

  // --- path tool ---
  const pathA = $<HTMLSelectElement>("path-a"), pathB = $<HTMLSelectElement>("path-b");
  const pathItems = [{ value: "current", label: "current point" }, ...materialItems];
  fillSelect(pathA, pathItems, "0");
  fillSelect(pathB, pathItems, String(Math.min(1, model.count - 1)));
  const pointOf = (v: string) => (v === "current" ? state.x.slice() : model.latent[Number(v)].slice());
  let pathRun = 0;
  const showPath = async () => {
    const a = pointOf(pathA.value), b = pointOf(pathB.value);
    const steps = Math.max(2, Math.min(16, Number($<HTMLInputElement>("path-steps").value) || 8));
    // The ends are the exact points (a rounded endpoint would miss a material's exact weights).
    const samples = Array.from({ length: steps }, (_, k) =>
      k === steps - 1 ? b.slice() : a.map((v, d) => v + ((b[d] - v) * k) / (steps - 1)));
    map.path = { a, b, samples };
    map.redraw();
    const run = ++pathRun;
    const strip = $("strip");
    strip.replaceChildren(
      ...samples.map((x, k) => {
        const btn = document.createElement("button");
        btn.type = "button";
        btn.className = "strip-item";
        btn.title = `t = ${(k / (steps - 1)).toFixed(2)}: x = (${fmtX(x)})`;
        btn.addEventListener("click", () => {
          map.setPoint(x);
          moveTo(x, false);
        });
        const img = document.createElement("img");
        img.alt = btn.title;
        btn.append(img);
        return btn;
      }),
    );
    const imgs = strip.querySelectorAll("img");
    for (let k = 0; k < samples.length && run === pathRun; k++) {
      const blob = await api.preview(samples[k], state.env, state.object, 96);
      if (run === pathRun) await showBlob(imgs[k], blob);
    }
  };
  $("path-go").addEventListener("click", () => void showPath().catch((e) => setStatus(`path: ${e.message}`, true)));
  $("path-clear").addEventListener("click", () => {
    pathRun++;
    map.path = null;
    map.redraw();
    $("strip").replaceChildren();
  });

  // Start at the first material so that the page opens on something real.
  const start = model.latent[0].slice();
  map.setPoint(start);
  moveTo(start, false);
  refreshLayer();
}

main().catch((e) => {
  setStatus(`failed to load the model: ${(e as Error).message}`, true);
  $("model-info").textContent = "no model";
});
