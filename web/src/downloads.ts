// Downloads of a point or a model material for other renderers and artists' tools: the table as
// MERL .binary or RGL .bsdf (RGB for Mitsuba 3, spectral for pbrt-v4 and Mitsuba 3's spectral
// variants), and the analytic fit as glTF, MaterialX or a
// Blender script (docs/EXPORT.md). The fit's error (POST /api/fit) is shown before its files are
// offered. Used by the point tools' download menu and the short list's export (library.ts).
import { api, type FitReply, type Point } from "./api";
import { $, download } from "./dom";
import { materialAt, type PageStore } from "./state";
import { setStatus } from "./status";

export type DownloadFormat = "binary" | "bsdf" | "bsdf-spectral" | "gltf" | "mtlx" | "py";

export const formatLabels: { [f in DownloadFormat]: string } = {
  bsdf: "Mitsuba 3 (RGB .bsdf)", "bsdf-spectral": "pbrt-v4 (spectral .bsdf)", mtlx: "MaterialX (.mtlx)",
  gltf: "glTF (.gltf)", py: "Blender (.py)",
  binary: "MERL (.binary)",
};

export const isFit = (f: DownloadFormat): f is "gltf" | "mtlx" | "py" => f === "gltf" || f === "mtlx" || f === "py";

/** The server's file of point `x` (or of material `material`, its own table) in `format`. */
export function fileOf(x: Point, material: number | null, format: DownloadFormat): Promise<Blob> {
  return isFit(format) ? api.fitFile(x, material, format) : api.exportTable(x, material, format);
}

/** "relative RMS 12.3 %, albedo within 4.5 %": the fit's error against the table. */
export function fitErrorText(r: FitReply): string {
  const pct = (v: number) => `${(100 * v).toFixed(1)} %`;
  return `relative RMS ${pct(r.error.relative_rms)}, albedo within ${pct(r.error.albedo_error)}` +
    (r.fit.converged ? "" : " (did not converge)");
}

/** The file name extension of a format. */
export const extensionOf = (f: DownloadFormat): string => (f === "bsdf-spectral" ? "bsdf" : f);

/** A file name from a material's name. */
export const safeName = (name: string): string => name.replace(/[^\w.-]+/g, "_");

/** The point tools' download menu: the current point, or the material it is on. */
export function createDownloadMenu(store: PageStore): void {
  const model = store.state.model;
  const open = $<HTMLButtonElement>("download-open"), menu = $("download-menu"), error = $("fit-error");
  const fitButtons = (["gltf", "mtlx", "py"] as const).map((f) => $<HTMLButtonElement>(`export-${f}`));
  let fitted: { key: string; reply: FitReply } | null = null;
  let pending: AbortController | null = null;

  const subject = () => {
    const s = store.state, i = materialAt(s), x = s.x.slice();
    const name = i !== null ? model.names[i] : `matlas-${x.map((v) => v.toFixed(3)).join("_")}`;
    return { x, material: i, name, key: JSON.stringify([x, i]) };
  };
  // The fit of what the menu shows: asked for when the menu opens or the point moves under it.
  const refit = async () => {
    const s = subject();
    $("download-what").textContent = s.material !== null ? `material ${s.name}` : `point (${s.x.map((v) => v.toFixed(3)).join(", ")})`;
    if (fitted?.key === s.key) return;
    pending?.abort();
    const ctl = new AbortController();
    pending = ctl;
    fitted = null;
    fitButtons.forEach((b) => (b.disabled = true));
    menu.dataset.fit = "pending";
    error.textContent = "fitting… (seconds)";
    try {
      const reply = await api.fit(s.x, s.material, ctl.signal);
      if (ctl.signal.aborted) return;
      fitted = { key: s.key, reply };
      // Far from the data the table itself is an extrapolation (as `matlas fit` warns).
      const v = reply.predictive_variance, fade = model.uncertainty?.fade_from;
      const far = v !== undefined && fade !== undefined && v >= fade;
      error.textContent = fitErrorText(reply) + (far ? `; far from the data (variance ${v.toPrecision(2)}): an extrapolation` : "");
      error.title = `glTF metallic-roughness fit: base colour ${reply.parameters.base_color.map((v) => v.toFixed(3)).join(" ")}, ` +
        `metallic ${reply.parameters.metallic.toFixed(2)}, roughness ${reply.parameters.roughness.toFixed(3)}` +
        (Math.max(...reply.parameters.sheen_color) > 0
          ? `, sheen ${reply.parameters.sheen_color[0].toFixed(2)} (roughness ${reply.parameters.sheen_roughness.toFixed(2)})`
          : "") + "; " +
        "relative RMS: cosine-weighted, against the table; albedo: largest difference at 0-75°";
      fitButtons.forEach((b) => (b.disabled = false));
      menu.dataset.fit = "ready";
    } catch (e) {
      if (ctl.signal.aborted) return;
      error.textContent = `fit failed: ${(e as Error).message}`;
      menu.dataset.fit = "failed";
    }
  };
  const show = (on: boolean) => {
    menu.hidden = !on;
    open.setAttribute("aria-expanded", String(on));
    if (on) void refit();
  };
  open.addEventListener("click", () => show(menu.hidden));
  document.addEventListener("keydown", (e) => { if (e.key === "Escape" && !menu.hidden) show(false); });
  store.on(["x"], () => { if (!menu.hidden) void refit(); });

  for (const format of ["binary", "bsdf", "bsdf-spectral", "gltf", "mtlx", "py"] as const) {
    $(`export-${format}`).addEventListener("click", async () => {
      const s = subject();
      try {
        setStatus(`preparing ${formatLabels[format]} of ${s.name}…`);
        download(await fileOf(s.x, s.material, format), `${safeName(s.name)}.${extensionOf(format)}`);
        const fit = isFit(format) && fitted?.key === s.key ? ` (fit: ${fitErrorText(fitted.reply)})` : "";
        setStatus(`downloaded ${formatLabels[format]} of ${s.name}${fit}`);
      } catch (e) {
        setStatus(`export: ${(e as Error).message}`, true, "export");
      }
    });
  }
}
