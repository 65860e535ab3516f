// Sparse measurements on the map (issue 30): a sample file (CSV or JSON, docs/ACQUISITION.md)
// chosen with "samples…" or dropped on the map is fitted by the server (POST /api/fit-samples);
// the map shows where it lands with its 2-sigma uncertainty ellipse, the current point moves
// there (the views show the fitted material), and the fit panel under the map sums it up
// (samples used, outliers, residual, best input). "plan…" downloads the directions to measure
// (POST /api/sample-plan): a fresh plan, or the next ones given the samples last fitted.
// A .binary file dropped on the map is projected, as the "upload…" button does.
import { api, type FitSamplesReply } from "./api";
import { $, download, fmtX } from "./dom";
import type { LatentMap } from "./map";
import { moveTo, type PageStore } from "./state";
import { setStatus } from "./status";

const MAX_BYTES = 1 << 20;

/** A number for the panel: 3 significant digits. */
const num = (v: number | null) => (v === null || !Number.isFinite(v) ? "–" : v.toPrecision(3));

export function createFitSamples(store: PageStore, map: LatentMap, project: (file: File) => Promise<void>): void {
  const model = store.state.model;
  const panel = $("fit-panel");
  const body = $("fit-body");
  const title = $("fit-title");
  let lastFile: File | null = null;

  const clear = () => {
    map.fitted = null;
    map.redraw();
    panel.hidden = true;
    store.update({ fitted: null });
  };
  $("fit-close").addEventListener("click", clear);

  const showError = (name: string, message: string) => {
    panel.hidden = false;
    panel.classList.add("failed");
    title.textContent = name;
    const p = document.createElement("p");
    p.className = "fit-error";
    p.setAttribute("role", "alert");
    p.textContent = message;
    body.replaceChildren(p);
    $("fit-go").hidden = true;
    setStatus(`samples: ${message}`, true, "samples");
  };

  const row = (label: string, text: string, cls = "") => {
    const div = document.createElement("div");
    div.className = `fit-row ${cls}`.trim();
    const b = document.createElement("b");
    b.textContent = label;
    const span = document.createElement("span");
    span.textContent = text;
    div.append(b, span);
    return div;
  };

  const show = (name: string, r: FitSamplesReply) => {
    panel.hidden = false;
    panel.classList.remove("failed");
    title.textContent = name;
    const extent = model.bounds.max.map((v, d) => v - model.bounds.min[d]);
    const outlierLines = r.samples.filter((s) => s.outlier).map((s) => s.line);
    const outliers = r.outliers === 0 ? "no outliers"
      : `${r.outliers} outlier${r.outliers === 1 ? "" : "s"} (${fileUnit(name)} ${outlierLines.slice(0, 6).join(", ")}${outlierLines.length > 6 ? ", …" : ""})`;
    const rows: HTMLElement[] = [
      row("fit", `${r.used} samples used · ${outliers} · RMS residual ${num(r.rms_residual)} (${r.transform})` +
        (r.skipped.length ? ` · ${r.skipped.length} skipped` : "") + (r.unusable.length ? ` · ${r.unusable.length} without data` : ""),
        r.outliers ? "warn" : ""),
      row("best input", r.best_input?.name ?? "–"),
      row("mix", r.weights.slice(0, 3).map((w) => `${w.name} ${w.weight.toFixed(2)}`).join(" · ") || "–"),
      ...(r.combined ? [row("off the map", "the samples are explained better by this mix of inputs than by any map point; " +
        "the views show the map point x it was pulled towards (.binary exports that point, not the mix)", "warn")] : []),
      row("x", `(${fmtX(r.x)}) ± (${r.latent_sigma.map((s, d) => twoSigma(s, extent[d])).join(", ")}) (2σ)`),
    ];
    const problems = [...r.skipped, ...r.unusable];
    if (problems.length) {
      const details = document.createElement("details");
      const summary = document.createElement("summary");
      summary.textContent = `${problems.length} row${problems.length === 1 ? "" : "s"} not used`;
      const list = document.createElement("ul");
      for (const p of problems.slice(0, 20)) {
        const li = document.createElement("li");
        li.textContent = p;
        list.append(li);
      }
      details.append(summary, list);
      rows.push(details);
    }
    body.replaceChildren(...rows);
    $("fit-go").hidden = false;
  };

  /** Moves the current point to x (inside the domain the server accepts). */
  const goTo = (x: number[]) => {
    const d = model.domain;
    const inside = x.map((v, i) => Math.min(d.max[i], Math.max(d.min[i], v)));
    map.setPoint(inside);
    moveTo(store, inside, false);
  };
  $("fit-go").addEventListener("click", () => {
    const f = store.state.fitted;
    if (f) goTo(f.reply.x);
  });

  const fit = async (file: File) => {
    if (file.size > MAX_BYTES) {
      showError(file.name, `the file has ${file.size} bytes; sample files are at most 1 MiB`);
      return;
    }
    setStatus(`fitting ${file.name}…`);
    try {
      const reply = await api.fitSamples(file);
      lastFile = file;
      const label = file.name.replace(/\.(csv|json|txt)$/i, "");
      map.fitted = { x: reply.x, covariance: reply.covariance, label };
      store.update({ fitted: { file: file.name, reply } });
      show(file.name, reply);
      goTo(reply.x);
      setStatus(`${file.name}: ${reply.used} samples fitted at (${fmtX(reply.x)})` +
        (reply.best_input ? `, closest to ${reply.best_input.name}` : ""));
    } catch (err) {
      map.fitted = null;
      map.redraw();
      store.update({ fitted: null });
      showError(file.name, (err as Error).message);
    }
  };

  $<HTMLInputElement>("samples-upload").addEventListener("change", async (e) => {
    const input = e.target as HTMLInputElement;
    const file = input.files?.[0];
    input.value = "";
    if (file) await fit(file);
  });

  // Drag and drop onto the map: sample files are fitted, MERL tables projected.
  const wrap = $("map-wrap");
  wrap.addEventListener("dragover", (e) => {
    if (!e.dataTransfer?.types.includes("Files")) return;
    e.preventDefault();
    e.dataTransfer.dropEffect = "copy";
    wrap.classList.add("drop-target");
  });
  wrap.addEventListener("dragleave", () => wrap.classList.remove("drop-target"));
  wrap.addEventListener("drop", (e) => {
    wrap.classList.remove("drop-target");
    const file = e.dataTransfer?.files?.[0];
    if (!file) return;
    e.preventDefault();
    void (/\.binary$/i.test(file.name) ? project(file) : fit(file));
  });

  $("sample-plan").addEventListener("click", async () => {
    const k = lastFile ? 10 : 20;
    setStatus(lastFile ? `planning the next ${k} directions after ${lastFile.name}…` : `planning ${k} directions…`);
    try {
      const plan = await api.samplePlan(k, lastFile ?? undefined);
      download(new Blob([plan.csv], { type: "text/csv" }), `matlas-plan-${plan.directions.length}.csv`);
      store.update({ plan: { k: plan.directions.length, conditionedOn: plan.conditioned_on } });
      setStatus(`downloaded a plan of ${plan.directions.length} directions` +
        (plan.conditioned_on ? ` given ${plan.conditioned_on} measured samples` : "") + ": measure them, fill in r, g, b and upload it");
    } catch (err) {
      setStatus(`plan: ${(err as Error).message}`, true, "samples");
    }
  });
}

/**
 * 2 sigma of a latent coordinate for the panel; beyond the map's extent on that axis the samples
 * do not pin the coordinate down (the table barely changes along it there): "free".
 */
function twoSigma(sigma: number | null, extent: number): string {
  if (sigma === null || !Number.isFinite(sigma)) return "?";
  return 2 * sigma > extent ? "free" : (2 * sigma).toFixed(4);
}

/** How a file names its samples: JSON files by sample number, CSV files by line. */
function fileUnit(name: string): string {
  return /\.json$/i.test(name) ? "samples" : "lines";
}
