// Retrying while the server answers 503 (busy, or a preview scene being prepared: docs/API.md),
// with exponential backoff, until it answers, fails otherwise, or the caller aborts.
import { ApiError } from "./api";

export interface Waiting {
  /** Attempts answered 503 so far. */
  attempts: number;
  /** Time since the first attempt. */
  waitedMs: number;
  /** Delay before the next attempt. */
  delayMs: number;
  /** The server's message. */
  message: string;
}

export interface RetryOptions {
  signal?: AbortSignal;
  /** Called before each wait. */
  onWait?: (w: Waiting) => void;
  firstDelayMs?: number;
  maxDelayMs?: number;
  /** Give up (rethrow the 503) after waiting this long. */
  giveUpMs?: number;
}

export async function retryWhileBusy<R>(task: (signal?: AbortSignal) => Promise<R>, o: RetryOptions = {}): Promise<R> {
  const start = performance.now();
  let delay = o.firstDelayMs ?? 400;
  for (let attempts = 1; ; attempts++) {
    try {
      return await task(o.signal);
    } catch (e) {
      const waitedMs = performance.now() - start;
      if (!(e instanceof ApiError) || e.status !== 503 || waitedMs > (o.giveUpMs ?? 300_000)) throw e;
      o.onWait?.({ attempts, waitedMs, delayMs: delay, message: e.message });
      await sleep(delay, o.signal);
      delay = Math.min(o.maxDelayMs ?? 3000, delay * 1.6);
    }
  }
}

export function sleep(ms: number, signal?: AbortSignal): Promise<void> {
  return new Promise((resolve, reject) => {
    if (signal?.aborted) return reject(signal.reason);
    const timer = setTimeout(resolve, ms);
    signal?.addEventListener("abort", () => {
      clearTimeout(timer);
      reject(signal.reason);
    }, { once: true });
  });
}

export function isAbort(e: unknown): boolean {
  return e instanceof DOMException && e.name === "AbortError";
}
