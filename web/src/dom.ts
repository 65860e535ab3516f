// Small DOM helpers shared by the page's views.

export const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

export function fmtX(x: number[]): string {
  return x.map((v) => v.toFixed(4)).join(", ");
}

export function download(blob: Blob, name: string): void {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

export function fillSelect(sel: HTMLSelectElement, items: { value: string; label: string }[], value?: string): void {
  sel.replaceChildren(...items.map((it) => new Option(it.label, it.value)));
  if (value !== undefined) sel.value = value;
}

/** Shows `blob` in `img` (a blob: URL) once decoded, and releases the previous blob URL. */
export async function showBlob(img: HTMLImageElement, blob: Blob): Promise<void> {
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
