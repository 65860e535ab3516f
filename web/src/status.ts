// The status line under the preview. Each message has a source (preview, panels, export...); an
// error stays until a later request of the same source succeeds (or any newer message replaces
// it), so a failure that has since been resolved does not linger.
import { $ } from "./dom";

let owner: string | null = null;

/** Shows `text`; `error` in red, attributed to `source`. */
export function setStatus(text: string, error = false, source: string | null = null): void {
  const s = $("status");
  s.textContent = text;
  s.classList.toggle("error", error);
  owner = error ? source : null;
}

/** A request of `source` succeeded: its error, if it is the one shown, is stale. */
export function clearError(source: string): void {
  if (owner === source) setStatus("");
}
