// Downloads of a point or a model material for other renderers and artists' tools: the table as
// MERL .binary or RGL .bsdf (RGB for Mitsuba 3, spectral for pbrt-v4 and Mitsuba 3's spectral
// variants), the analytic fit as glTF, MaterialX or a Blender script, and the fit of Blender
// 2.8-3.6's own Principled BSDF as its script (docs/EXPORT.md). Each fit's error (POST /api/fit)
// is shown before its files are offered. Used by the point tools' download menu and the short
// list's export (library.ts).
import { api, type FitModel, type FitReply, type Point } from "./api";
import { $, download } from "./dom";
import { materialAt, type PageStore } from "./state";
import { setStatus } from "./status";

export type DownloadFormat = "binary" | "bsdf" | "bsdf-spectral" | "gltf" | "mtlx" | "py" | "py-v1";

export const formatLabels: { [f in DownloadFormat]: string } = {
  bsdf: "Mitsuba 3 (RGB .bsdf)", "bsdf-spectral": "pbrt-v4 (spectral .bsdf)", mtlx: "MaterialX (.mtlx)",
  gltf: "glTF (.gltf)", py: "Blender 4 (.py)", "py-v1": "Blender 2.8-3.6 (.py)",
  binary: "MERL (.binary)",
};

type FitFormat = "gltf" | "mtlx" | "py" | "py-v1";
export const isFit = (f: DownloadFormat): f is FitFormat => f === "gltf" || f === "mtlx" || f === "py" || f === "py-v1";

/** The model a fitted format needs: Blender 2.8-3.6's Principled BSDF for its script, else glTF's. */
export const fitModelOf = (f: FitFormat): FitModel => (f === "py-v1" ? "principled-v1" : "gltf");

/** The server's file of point `x` (or of material `material`, its own table) in `format`. */
export function fileOf(x: Point, material: number | null, format: DownloadFormat): Promise<Blob> {
  if (!isFit(format)) return api.exportTable(x, material, format);
  return api.fitFile(x, material, format === "py-v1" ? "py" : format, fitModelOf(format));
}

/** "relative RMS 12.3 %, albedo within 4.5 %": the fit's error against the table. */
export function fitErrorText(r: FitReply): string {
  const pct = (v: number) => `${(100 * v).toFixed(1)} %`;
  return `relative RMS ${pct(r.error.relative_rms)}, albedo within ${pct(r.error.albedo_error)}` +
    (r.fit.converged ? "" : " (did not converge)");
}

/** The file name extension of a format. */
export const extensionOf = (f: DownloadFormat): string => (f === "bsdf-spectral" ? "bsdf" : f === "py-v1" ? "py" : f);

/** A file name from a material's name. */
export const safeName = (name: string): string => name.replace(/[^\w.-]+/g, "_");

/** The point tools' download menu: the current point, or the material it is on. */
export function createDownloadMenu(store: PageStore): void {
  const model = store.state.model;
  const open = $<HTMLButtonElement>("download-open"), menu = $("download-menu");
  // Each model's fit: its error line, its buttons and its reply for the subject shown. The glTF
  // fit is asked for first (its three files), then Blender 2.8-3.6's.
  const fits: { model: FitModel; error: HTMLElement; buttons: HTMLButtonElement[]; fitted: { key: string; reply: FitReply } | null }[] = [
    { model: "gltf", error: $("fit-error"), buttons: (["gltf", "mtlx", "py"] as const).map((f) => $<HTMLButtonElement>(`export-${f}`)),
      fitted: null },
    { model: "principled-v1", error: $("fit-error-v1"), buttons: [$<HTMLButtonElement>("export-py-v1")], fitted: null },
  ];
  let pending: AbortController | null = null;

  const subject = () => {
    const s = store.state, i = materialAt(s), x = s.x.slice();
    const name = i !== null ? model.names[i] : `matlas-${x.map((v) => v.toFixed(3)).join("_")}`;
    return { x, material: i, name, key: JSON.stringify([x, i]) };
  };
  // The fits of what the menu shows: asked for when the menu opens or the point moves under it.
  const refit = async () => {
    const s = subject();
    $("download-what").textContent = s.material !== null ? `material ${s.name}` : `point (${s.x.map((v) => v.toFixed(3)).join(", ")})`;
    if (fits.every((f) => f.fitted?.key === s.key)) return;
    pending?.abort();
    const ctl = new AbortController();
    pending = ctl;
    for (const f of fits) {
      if (f.fitted?.key === s.key) continue;
      f.fitted = null;
      f.buttons.forEach((b) => (b.disabled = true));
      f.error.textContent = "fitting… (seconds)";
      f.error.title = "";
    }
    menu.dataset.fit = "pending";
    for (const f of fits) {
      if (f.fitted?.key === s.key) continue;
      try {
        const reply = await api.fit(s.x, s.material, ctl.signal, f.model);
        if (ctl.signal.aborted) return;
        f.fitted = { key: s.key, reply };
        // Far from the data the table itself is an extrapolation (as `matlas fit` warns).
        const v = reply.predictive_variance, fade = model.uncertainty?.fade_from;
        const far = v !== undefined && fade !== undefined && v >= fade;
        f.error.textContent = fitErrorText(reply) + (far ? `; far from the data (variance ${v.toPrecision(2)}): an extrapolation` : "");
        f.error.title = parametersText(reply) + "; relative RMS: cosine-weighted, against the table; albedo: largest difference at 0-75°";
        f.buttons.forEach((b) => (b.disabled = false));
        if (f.model === "gltf") menu.dataset.fit = "ready";
      } catch (e) {
        if (ctl.signal.aborted) return;
        f.error.textContent = `fit failed: ${(e as Error).message}`;
        if (f.model === "gltf") menu.dataset.fit = "failed";
      }
    }
    menu.dataset.fitV1 = fits[1].fitted ? "ready" : "failed";
  };
  const show = (on: boolean) => {
    menu.hidden = !on;
    open.setAttribute("aria-expanded", String(on));
    if (on) void refit();
  };
  open.addEventListener("click", () => show(menu.hidden));
  document.addEventListener("keydown", (e) => { if (e.key === "Escape" && !menu.hidden) show(false); });
  store.on(["x"], () => { if (!menu.hidden) void refit(); });

  for (const format of ["binary", "bsdf", "bsdf-spectral", "gltf", "mtlx", "py", "py-v1"] as const) {
    $(`export-${format}`).addEventListener("click", async () => {
      const s = subject();
      try {
        setStatus(`preparing ${formatLabels[format]} of ${s.name}…`);
        download(await fileOf(s.x, s.material, format), `${safeName(s.name)}.${extensionOf(format)}`);
        const fitted = isFit(format) ? fits.find((f) => f.model === fitModelOf(format))?.fitted : null;
        const fit = fitted?.key === s.key ? ` (fit: ${fitErrorText(fitted.reply)})` : "";
        setStatus(`downloaded ${formatLabels[format]} of ${s.name}${fit}`);
      } catch (e) {
        setStatus(`export: ${(e as Error).message}`, true, "export");
      }
    });
  }
}

/** The fitted parameters in a line, as the model names them. */
function parametersText(r: FitReply): string {
  const base = r.parameters.base_color.map((v) => v.toFixed(3)).join(" ");
  if (r.kind === "principled-v1") {
    const q = r.parameters;
    return `Blender 2.8-3.6 Principled BSDF: base colour ${base}, metallic ${q.metallic.toFixed(2)}, specular ` +
      `${q.specular.toFixed(2)}, roughness ${q.roughness.toFixed(3)}` + (q.sheen > 0 ? `, sheen ${q.sheen.toFixed(2)}` : "") +
      (q.coat > 0 ? `, coat ${q.coat.toFixed(2)} (roughness ${q.coat_roughness.toFixed(2)})` : "");
  }
  const g = r.parameters;
  return `glTF metallic-roughness fit: base colour ${base}, metallic ${g.metallic.toFixed(2)}, roughness ${g.roughness.toFixed(3)}` +
    (Math.max(...g.sheen_color) > 0 ? `, sheen ${g.sheen_color[0].toFixed(2)} (roughness ${g.sheen_roughness.toFixed(2)})` : "");
}
