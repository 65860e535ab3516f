// Whether a preview scene (environment x object) is ready on the server: GET /api/preview/status,
// polled while the server prepares it (never retrying into 503s, which also fill the console with
// errors). Scenes found ready are remembered for the page's lifetime; a scene the server later
// drops from memory answers 503 once, which the callers retry (retry.ts).
import { api, type PreviewStatus } from "./api";
import { sleep } from "./retry";

const ready = new Set<string>();

/**
 * Resolves once the scene is ready; `onWait` hears every status while it is not (with the time
 * waited and the number of polls so far). Rejects with the server's error if preparing it failed.
 */
export async function sceneReady(env: string, object: string, signal?: AbortSignal,
                                 onWait?: (status: PreviewStatus, waitedMs: number, polls: number) => void): Promise<void> {
  const key = `${env}/${object}`;
  const start = performance.now();
  for (let polls = 0; !ready.has(key); polls++) {
    const st = await api.previewStatus(env, object, signal);
    if (st.error) throw new Error(`the scene ${key} could not be prepared: ${st.error}`);
    if (st.ready) {
      ready.add(key);
      return;
    }
    onWait?.(st, performance.now() - start, polls);
    await sleep(polls < 4 ? 250 : 600, signal);
  }
}
