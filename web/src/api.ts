// Typed client of the matlas JSON API (docs/API.md).

export interface ModelInfo {
  name: string;
  count: number;
  dim: number;
  names: string[];
  latent: number[][];
  /** sRGB colour (0..255) of each material's albedo at normal incidence. */
  colors: [number, number, number][];
  bounds: { min: number[]; max: number[] };
  domain: { min: number[]; max: number[] };
  dims: [number, number, number];
  scenes: { envs: string[]; objects: string[]; default_env: string; default_object: string };
  preview: { size: number; drag_size: number; max_size: number };
  layers: string[];
  /** How m(x) mixes the inputs: "gp" (the paper's GP weights) or "convex"; absent in older servers. */
  interpolation?: string;
  /** Predictive variances over which the albedo layer fades into "no data here". */
  uncertainty?: { fade_from: number; fade_to: number };
}

export interface Plausibility {
  /** Share of negative values in a fixed sample of the table's columns. */
  negative_fraction: number;
  max_albedo: number;
  min_albedo: number;
  sampled_values: number;
  plausible: boolean;
}

export interface WeightsReply {
  weights: number[];
  variance: number;
  top: { index: number; name: string; weight: number }[];
  plausibility: Plausibility;
}

export interface LobeReply {
  theta_i: number;
  theta_o: number[];
  rgb: [number, number, number][];
}

export interface AlbedoReply {
  theta_o: number[];
  rgb: [number, number, number][];
}

export interface ProjectReply {
  x: number[];
  residual: number;
  variance: number;
  top: { index: number; name: string; weight: number }[];
}

export class ApiError extends Error {
  constructor(readonly status: number, message: string) {
    super(message);
  }
}

async function check(res: Response): Promise<Response> {
  if (res.ok) return res;
  let message = `${res.status} ${res.statusText}`;
  try {
    const body = await res.json();
    if (body && typeof body.error === "string") message = body.error;
  } catch {
    /* not JSON */
  }
  throw new ApiError(res.status, message);
}

function post(path: string, body: unknown, signal?: AbortSignal): Promise<Response> {
  return fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body),
    signal,
  }).then(check);
}

export const api = {
  model: (): Promise<ModelInfo> => fetch("api/model").then(check).then((r) => r.json()),
  preview: (x: number[], env: string, object: string, size: number, signal?: AbortSignal): Promise<Blob> =>
    post("api/preview", { x, env, object, size }, signal).then((r) => r.blob()),
  weights: (x: number[], top = 8): Promise<WeightsReply> => post("api/weights", { x, top }).then((r) => r.json()),
  slice: (x: number[], phi_d: number): Promise<Blob> => post("api/slice", { x, phi_d }).then((r) => r.blob()),
  lobe: (x: number[], theta_i: number): Promise<LobeReply> =>
    post("api/lobe", { x, theta_i, samples: 181 }).then((r) => r.json()),
  albedo: (x: number[]): Promise<AlbedoReply> => post("api/albedo", { x }).then((r) => r.json()),
  map: (body: {
    layer: string;
    axes: [number, number];
    x: number[];
    rect: [number, number, number, number];
    size: [number, number];
  }): Promise<Blob> => post("api/map", body).then((r) => r.blob()),
  exportMerl: (x: number[]): Promise<Blob> => post("api/export", { x }).then((r) => r.blob()),
  project: (file: Blob): Promise<ProjectReply> =>
    fetch("api/project", { method: "POST", headers: { "Content-Type": "application/octet-stream" }, body: file })
      .then(check)
      .then((r) => r.json()),
  thumbnailUrl: (index: number, env: string, object: string): string =>
    `api/thumbnail/${index}?env=${encodeURIComponent(env)}&object=${encodeURIComponent(object)}`,
};
