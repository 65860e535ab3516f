// The designer's tools around the map: search by name (the top bar; goes to the material and
// filters the database grid), the name of the material at the current point (or what it mixes),
// the database as a grid of thumbnails, and the short list: materials side by side in the same
// scene (server previews of one size, one exposure), exported together in any download format
// (downloads.ts).
import { api, type FitReply } from "./api";
import { $, download, fmtX, showBlob } from "./dom";
import { extensionOf, fileOf, fitModelOf, formatLabels, isFit, safeName, type DownloadFormat } from "./downloads";
import type { LatentMap } from "./map";
import { retryWhileBusy } from "./retry";
import { sceneReady } from "./scene-ready";
import { materialAt, moveTo, type ListItem, type PageStore } from "./state";
import { clearError, setStatus } from "./status";

export function createLibrary(store: PageStore, map: LatentMap): void {
  const model = store.state.model;
  const goTo = (x: number[]) => {
    map.setPoint(x);
    moveTo(store, x.slice(), false);
  };

  // --- search: a datalist of the names; Enter or picking a name goes there -------------------
  const search = $<HTMLInputElement>("search");
  $("material-names").replaceChildren(...model.names.map((n) => new Option(n)));
  const find = (text: string): number => {
    const t = text.trim().toLowerCase();
    if (!t) return -1;
    const exact = model.names.findIndex((n) => n.toLowerCase() === t);
    return exact >= 0 ? exact : model.names.findIndex((n) => n.toLowerCase().includes(t));
  };
  const goToText = () => {
    const i = find(search.value);
    if (i < 0) {
      if (search.value.trim()) setStatus(`no material named like "${search.value.trim()}"`, true, "search");
      return;
    }
    clearError("search");
    search.value = model.names[i];
    goTo(model.latent[i]);
    filter();
  };
  search.addEventListener("keydown", (e) => {
    if (e.key === "Enter") goToText();
    if (e.key === "Escape") {
      search.value = "";
      filter();
      search.blur();
    }
  });
  search.addEventListener("input", () => {
    // Picking a datalist entry fires input with the exact name: go there at once.
    if (model.names.includes(search.value)) goToText();
    else filter();
  });

  // --- the database grid ----------------------------------------------------------------------
  const library = $("library");
  const tiles = model.names.map((name, i) => {
    const tile = tileOf(name, () => goTo(model.latent[i]), "+", () => toggle({ name, x: model.latent[i].slice(), index: i }));
    tile.dataset.index = String(i);
    return tile;
  });
  library.replaceChildren(...tiles);
  const setThumbs = (env: string, object: string) => {
    tiles.forEach((t, i) => {
      const img = t.querySelector("img")!;
      img.dataset.index = String(i);
      const url = api.thumbnailUrl(i, env, object);
      if (img.getAttribute("src") !== url) img.src = url;
    });
  };
  function filter(): void {
    const t = search.value.trim().toLowerCase();
    const exact = model.names.some((n) => n.toLowerCase() === t);
    let shown = 0;
    tiles.forEach((tile, i) => {
      tile.hidden = !exact && t !== "" && !model.names[i].toLowerCase().includes(t);
      if (!tile.hidden) ++shown;
    });
    $("library-count").textContent = shown === model.count ? `${model.count} materials` : `${shown} of ${model.count} match "${search.value.trim()}"`;
  }
  // A new scene's thumbnails once the server has it ready (polled, scene-ready.ts: no 503s);
  // meanwhile the previous scene's stay (at first the default scene's).
  let thumbRun: AbortController | null = null;
  const showThumbs = async () => {
    thumbRun?.abort();
    const signal = (thumbRun = new AbortController()).signal;
    const { env, object } = store.state;
    try {
      await sceneReady(env, object, signal);
    } catch {
      return;  // aborted by a newer scene, or the scene failed (the reference render says so)
    }
    if (!signal.aborted) setThumbs(env, object);
  };
  setThumbs(model.scenes.default_env, model.scenes.default_object);
  void showThumbs();
  filter();

  // --- the current point: its material's name, or what it mixes -------------------------------
  const atMaterial = $("at-material");
  let current: number | null = null;
  const showWhere = () => {
    const s = store.state;
    const i = materialAt(s);
    if (i !== current) {
      tiles[current ?? -1]?.classList.remove("current");
      tiles[i ?? -1]?.classList.add("current");
      current = i;
    }
    // "go to material" must not keep a name once the point has moved away from it.
    const typed = model.names.indexOf(search.value);
    if (typed >= 0 && typed !== i) {
      search.value = "";
      filter();
    }
    let text = "";
    if (i !== null) text = model.names[i];
    else if (s.lastWeights && s.lastWeights.x.every((v, d) => v === s.x[d])) {
      text = "≈ " + s.lastWeights.top.filter((t) => t.weight >= 0.05).slice(0, 3)
        .map((t) => `${Math.round(100 * t.weight)} % ${t.name}`).join(" + ");
    }
    atMaterial.textContent = text;
    atMaterial.title = text;
  };
  store.on(["x", "lastWeights"], showWhere);
  showWhere();

  // --- the short list and the comparison ------------------------------------------------------
  const compare = $("compare");
  let run: AbortController | null = null;
  const same = (a: ListItem, b: ListItem) => a.x.length === b.x.length && a.x.every((v, d) => v === b.x[d]);
  function toggle(item: ListItem): void {
    const list = store.state.shortlist;
    const k = list.findIndex((it) => same(it, item));
    store.update({ shortlist: k >= 0 ? list.filter((_, j) => j !== k) : [...list, item] });
  }
  const renderList = async () => {
    run?.abort();
    const signal = (run = new AbortController()).signal;
    const list = store.state.shortlist;
    $("list-count").textContent = list.length ? `${list.length} listed` : "";
    const listed = new Set(list.filter((it) => it.index !== null).map((it) => it.index));
    tiles.forEach((t, i) => {
      t.classList.toggle("listed", listed.has(i));
      t.querySelector(".tile-btn")!.textContent = listed.has(i) ? "✓" : "+";
    });
    const items = list.map((it) => tileOf(it.name, () => goTo(it.x), "×", () => toggle(it)));
    items.forEach((t) => (t.querySelector("img")!.loading = "eager"));  // blob images, shown once decoded
    items.forEach((t, k) => (t.title = `${list[k].name}: x = (${fmtX(list[k].x)})`));
    compare.replaceChildren(...items);
    const { env, object } = store.state, size = model.preview.size;
    compare.dataset.scene = `${env}/${object}`;
    compare.dataset.ready = "0";
    try {
      if (list.length) await sceneReady(env, object, signal);  // polled, not retried into 503s (scene-ready.ts)
      for (let k = 0; k < list.length && !signal.aborted; k++) {
        const blob = await retryWhileBusy((s) => api.preview(list[k].x, env, object, size, s), { signal });
        if (signal.aborted) return;
        await showBlob(items[k].querySelector("img")!, blob);
        compare.dataset.ready = String(k + 1);
      }
      clearError("compare");
    } catch (e) {
      if (!signal.aborted) setStatus(`compare: ${(e as Error).message}`, true, "compare");
    }
  };
  store.on(["shortlist"], () => void renderList());
  store.on(["env", "object"], () => {
    void showThumbs();
    void renderList();
  });
  $("list-add").addEventListener("click", () => {
    const s = store.state;
    const i = materialAt(s);
    const item = i !== null ? { name: model.names[i], x: model.latent[i].slice(), index: i }
      : { name: `point (${s.x.map((v) => v.toFixed(3)).join(", ")})`, x: s.x.slice(), index: null };
    if (!s.shortlist.some((it) => same(it, item))) store.update({ shortlist: [...s.shortlist, item] });
  });
  $("list-clear").addEventListener("click", () => store.update({ shortlist: [] }));
  $("list-export").addEventListener("click", async () => {
    const list = store.state.shortlist;
    if (list.length === 0) return setStatus("the short list is empty: add materials with + list or a thumbnail's +");
    const format = $<HTMLSelectElement>("list-format").value as DownloadFormat;
    try {
      // An analytic format: every fit first, so that list.json carries their errors.
      const fits: (FitReply | null)[] = [];
      for (const [k, it] of list.entries()) {
        if (!isFit(format)) break;
        setStatus(`fitting ${k + 1} of ${list.length}: ${it.name}…`);
        fits.push(await api.fit(it.x, it.index, undefined, fitModelOf(format)));
      }
      const body = {
        model: model.name, q: model.dim, format,
        materials: list.map((it, k) => ({
          name: it.name, x: it.x, index: it.index,
          ...(fits[k] ? { fit_error: { relative_rms: fits[k]!.error.relative_rms, albedo_error: fits[k]!.error.albedo_error } } : {}),
        })),
      };
      download(new Blob([JSON.stringify(body, null, 2)], { type: "application/json" }), "matlas-list.json");
      for (const [k, it] of list.entries()) {
        setStatus(`exporting ${k + 1} of ${list.length}: ${it.name}…`);
        download(await fileOf(it.x, it.index, format), `${String(k + 1).padStart(2, "0")}-${safeName(it.name)}.${extensionOf(format)}`);
      }
      const worst = fits.length ? `; largest relative RMS ${(100 * Math.max(...fits.map((f) => f!.error.relative_rms))).toFixed(1)} %, ` +
        `albedo within ${(100 * Math.max(...fits.map((f) => f!.error.albedo_error))).toFixed(1)} %` : "";
      setStatus(`exported ${list.length} ${isFit(format) ? "fits" : "tables"} (${formatLabels[format]}) and matlas-list.json${worst}`);
    } catch (e) {
      setStatus(`export: ${(e as Error).message}`, true, "export");
    }
  });

  // The thumbnails fall back to the default scene's while the chosen one is prepared (503).
  const fallback = (e: Event) => {
    const img = e.target as HTMLImageElement;
    if (img.tagName !== "IMG" || img.dataset.index === undefined) return;
    const { default_env, default_object } = model.scenes;
    const url = api.thumbnailUrl(Number(img.dataset.index), default_env, default_object);
    if (img.getAttribute("src") !== url) img.src = url;
  };
  library.addEventListener("error", fallback, true);
}

/** A tile: an image (click: go there), a caption and a corner button. */
function tileOf(name: string, go: () => void, mark: string, act: () => void): HTMLElement {
  const tile = document.createElement("div");
  tile.className = "tile";
  const img = document.createElement("img");
  img.alt = name;
  img.loading = "lazy";
  img.title = `${name}: click to go there`;
  img.addEventListener("click", go);
  const btn = document.createElement("button");
  btn.type = "button";
  btn.className = "tile-btn";
  btn.textContent = mark;
  btn.title = mark === "×" ? "remove from the short list" : "add to (or remove from) the short list";
  btn.addEventListener("click", act);
  const caption = document.createElement("span");
  caption.className = "caption";
  caption.textContent = name;
  tile.append(img, btn, caption);
  return tile;
}
