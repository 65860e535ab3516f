// On-page guidance: the help dialog (the "?" button or the ? key), the first-run hint over the map
// (shown until the map is first used, then never again: localStorage), and the page's shortcuts
// that are not the map's own (/ focuses the search, ? opens the help).
import { $ } from "./dom";

const HINT_KEY = "matlas.hint.map.done";

function stored(key: string): boolean {
  try {
    return localStorage.getItem(key) === "1";
  } catch {
    return false;  // storage refused (private mode, file://): the hint shows every time
  }
}

function remember(key: string): void {
  try {
    localStorage.setItem(key, "1");
  } catch {
    /* nothing to do */
  }
}

/** Whether a keyboard event comes from a field the user types into. */
function typing(e: KeyboardEvent): boolean {
  const t = e.target as HTMLElement | null;
  return !!t && (t.tagName === "INPUT" || t.tagName === "SELECT" || t.tagName === "TEXTAREA" || t.isContentEditable);
}

export function createGuidance(): void {
  const help = $<HTMLDialogElement>("help");
  const open = () => {
    if (!help.open) help.showModal();
  };
  $("help-button").addEventListener("click", open);
  $("help-close").addEventListener("click", () => help.close());
  help.addEventListener("click", (e) => {
    if (e.target === help) help.close();  // a click on the backdrop
  });

  // The map hint: until the user has moved the point on the map once.
  const hint = $("map-hint");
  const dismiss = () => {
    hint.hidden = true;
    remember(HINT_KEY);
  };
  if (!stored(HINT_KEY)) hint.hidden = false;
  hint.querySelector("button")!.addEventListener("click", dismiss);
  const map = $("map");
  map.addEventListener("pointerdown", () => !hint.hidden && dismiss());
  map.addEventListener("keydown", (e) => e.key.startsWith("Arrow") && !hint.hidden && dismiss());

  document.addEventListener("keydown", (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey || typing(e)) return;
    if (e.key === "?") {
      e.preventDefault();
      open();
    } else if (e.key === "/") {
      e.preventDefault();
      $<HTMLInputElement>("search").focus();
    }
  });
}
