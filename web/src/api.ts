// Typed client of the matlas JSON API (docs/API.md).

// The types below mirror docs/api.schema.json one to one (same names, fields and optionality);
// web/tests/api-schema.test.mjs checks that they do, and that a live server's answers match.

/** A latent point: q numbers. */
export type Point = number[];
export type Rgb = [number, number, number];

export interface Range {
  min: Point;
  max: Point;
}

export interface TopWeight {
  index: number;
  name: string;
  weight: number;
}

export interface ErrorReply {
  error: string;
}

export interface ModelInfo {
  name: string;
  count: number;
  dim: number;
  names: string[];
  latent: Point[];
  /** sRGB colour (0..255) of each material's albedo at normal incidence. */
  colors: Rgb[];
  bounds: Range;
  domain: Range;
  dims: [number, number, number];
  scenes: { envs: string[]; objects: string[]; default_env: string; default_object: string };
  preview: { size: number; drag_size: number; max_size: number };
  layers: string[];
  /** Number of theta_o bins of the albedo curves. */
  albedo_angles: number;
  /** How m(x) mixes the inputs: "gp" (the paper's GP weights) or "convex"; absent in older servers. */
  interpolation?: "gp" | "convex";
  /** Predictive variances over which the albedo layer fades into "no data here". */
  uncertainty?: { fade_from: number; fade_to: number };
  /** Convex weights over inputs that are all plausible: every point is, and the plausibility layer fades like the albedo one. */
  plausible_everywhere: boolean;
  /** The scene view's GI scenes (GET /api/gi), those ready from the start first; absent without any. */
  gi?: { scenes: string[]; preloaded: string[]; views?: { [scene: string]: string[] } };
}

export interface PointRequest {
  x: Point;
}

/** POST /api/export: the table of the point, or of model material `material` (its own table). */
export interface ExportRequest {
  x: Point;
  material?: number;
  format?: "binary" | "bsdf" | "bsdf-spectral";
}

/** The analytic model fitted: glTF's metallic-roughness, or Blender 2.8-3.6's Principled BSDF. */
export type FitModel = "gltf" | "principled-v1";

export interface FitRequest {
  x: Point;
  material?: number;
  model?: FitModel;
}

export interface FitFileRequest {
  x: Point;
  material?: number;
  format: "gltf" | "mtlx" | "py";
  model?: FitModel;
}

/** The glTF metallic-roughness parameters of a fit (docs/EXPORT.md). */
export interface FitParameters {
  base_color: Rgb;
  metallic: number;
  roughness: number;
  specular: number;
  ior: number;
  clearcoat: number;
  clearcoat_roughness: number;
  /** KHR_materials_sheen (0 0 0: none). */
  sheen_color: Rgb;
  sheen_roughness: number;
}

/** The same parameters under OpenPBR Surface's names (the MaterialX document's inputs). */
export interface OpenPbrParameters {
  base_color: Rgb;
  base_metalness: number;
  specular_roughness: number;
  specular_weight: number;
  specular_ior: number;
  coat_weight: number;
  coat_roughness: number;
  coat_ior: number;
  fuzz_weight: number;
  fuzz_color: Rgb;
  fuzz_roughness: number;
}

export interface FitAlbedo {
  theta_deg: number;
  table: Rgb;
  fit: Rgb;
}

export interface FitErrors {
  relative_rms: number;
  cbrt_distance: number;
  albedo_error: number;
  albedo: FitAlbedo[];
}

export interface FitSearch {
  objective: number;
  samples: number;
  starts: number;
  evaluations: number;
  converged: boolean;
  restart_gain: number;
  seconds: number;
}

/** The inputs of Blender 2.8-3.6's Principled BSDF fitted, and its coat layer (docs/EXPORT.md). */
export interface PrincipledV1Parameters {
  base_color: Rgb;
  metallic: number;
  specular: number;
  specular_tint: number;
  roughness: number;
  sheen: number;
  sheen_tint: number;
  coat: number;
  coat_roughness: number;
}

export interface GltfFitReply {
  source: string;
  name: string;
  kind: "gltf";
  model: string;
  parameters: FitParameters;
  openpbr_surface: OpenPbrParameters;
  error: FitErrors;
  fit: FitSearch;
  predictive_variance?: number;
}

export interface PrincipledV1FitReply {
  source: string;
  name: string;
  kind: "principled-v1";
  model: string;
  parameters: PrincipledV1Parameters;
  error: FitErrors;
  fit: FitSearch;
  predictive_variance?: number;
}

/** POST /api/fit: the analytic fit of a point or material, with its error against the table. */
export type FitReply = GltfFitReply | PrincipledV1FitReply;

export interface PreviewRequest {
  x: Point;
  env?: string;
  object?: string;
  size?: number;
}

export interface PreviewStatus {
  env: string;
  object: string;
  ready: boolean;
  progress: number;
  stage: string;
  seconds: number;
  seconds_left?: number;
  error?: string;
}

export interface RefineRequest {
  x: Point;
  env?: string;
  object?: string;
  seconds?: number;
  denoise?: boolean;
}

/** POST /api/gi/refine: the scene view of a point refined at rest. */
export interface GiRefineRequest {
  x: Point;
  scene?: string;
  seconds?: number;
  exposure?: number | "auto";
  tone?: string;
  denoise?: boolean;
}

/** A refined preview (POST /api/preview/refine) and how far it has converged. */
export interface Refined {
  blob: Blob;
  spp: number;
  /** Estimated relative RMS error inside the object; null after the first pass. */
  error: number | null;
  converged: boolean;
  /** A newer preview request of this page stopped the pass: the image is the state before it. */
  interrupted: boolean;
  /** The image is denoised from the refinement's two halves (biased; `error` is the mean's). */
  denoised: boolean;
}

export interface WeightsRequest {
  x: Point;
  top?: number;
}

export interface SliceRequest {
  x: Point;
  phi_d?: number;
}

export interface LobeRequest {
  x: Point;
  theta_i?: number;
  samples?: number;
}

export interface MapRequest {
  layer?: "albedo" | "variance" | "plausibility";
  axes?: [number, number];
  x: Point;
  rect: [number, number, number, number];
  size: [number, number];
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
  x: Point;
  weights: number[];
  variance: number;
  top: TopWeight[];
  plausibility: Plausibility;
}

/** GET /api/interpolation: what the page needs to compute the weights itself (local-weights.ts). */
export interface InterpolationData {
  mode: "gp" | "convex";
  lengthscale: number;
  nugget: number;
  /** n points of q coordinates. */
  latent: number[][];
  taper_radius: number[];
  /** Lower Cholesky factor L of K = L L^T, n x n row-major. */
  cholesky: number[];
  /** The convex mode's metric A, n x n row-major. */
  metric: number[];
}

export interface LobeReply {
  theta_i: number;
  theta_o: number[];
  rgb: Rgb[];
}

export interface AlbedoReply {
  theta_o: number[];
  rgb: Rgb[];
}

export interface Nearest {
  index: number;
  name: string;
  residual: number;
}

export interface ProjectReply {
  x: Point;
  residual: number;
  variance: number;
  missing: number;
  nearest: Nearest | null;
  top: TopWeight[];
}

/** A number the server could not compute (JSON null), e.g. a covariance the samples leave undetermined. */
export type MaybeNumber = number | null;

export interface BestInput {
  index: number;
  name: string;
}

/** One measured sample of an uploaded file as the fit sees it (values in 1/sr, residuals in the layout's space). */
export interface FitSample {
  line: number;
  theta_i: number;
  phi_i: number;
  theta_o: number;
  phi_o: number;
  rgb: Rgb;
  predicted: Rgb;
  residual: Rgb;
  weight: Rgb;
  outlier: boolean;
}

/** POST /api/fit-samples: where a sample file lands on the map (docs/API.md). */
export interface FitSamplesReply {
  x: Point;
  variance: number;
  /** q x q covariance of x, rows. */
  covariance: MaybeNumber[][];
  latent_sigma: MaybeNumber[];
  weights: TopWeight[];
  best_input: BestInput | null;
  /** The fitted table is a convex combination of the inputs off the map (weights); x is the map's point. */
  combined: boolean;
  samples: FitSample[];
  used: number;
  outliers: number;
  rms_residual: number;
  scale: number;
  transform: string;
  skipped: string[];
  unusable: string[];
}

export interface PlannedDirection {
  theta_i: number;
  phi_i: number;
  theta_o: number;
  phi_o: number;
  wi: number[];
  wo: number[];
  gain: number;
}

/** POST /api/sample-plan: the directions to measure, and the plan as a sample file (CSV). */
export interface SamplePlanReply {
  directions: PlannedDirection[];
  remaining: number[];
  conditioned_on: number;
  skipped: string[];
  csv: string;
}

export interface RealtimeCamera {
  position: number[];
  target: number[];
  fov_degrees: number;
}

/** A light table's grid: float16 [theta_h][theta_d][phi_d][3] (docs/REALTIME.md "Direct lights"). */
export interface LightTableShape {
  theta_h: number;
  theta_d: number;
  phi_d: number;
  layout: string;
}

/** The real-time viewer's data shapes (GET /api/realtime, docs/REALTIME.md). */
export interface RealtimeInfo {
  bands: number;
  theta_o_count: number;
  /** K = (L + 1)(L + 2) / 2 */
  coefficients: number;
  materials: number;
  alpha: number[];
  band: number[];
  theta_o: number[];
  layout: string;
  /** Seconds the server took to load the coefficients from the cache beside the model, or to compute (and cache) them. */
  seconds: number;
  /** Whether they were loaded from the cache or computed. */
  cache: "loaded" | "computed";
  /** What happened to the cache (loaded, or why it was recomputed, and whether it was written). */
  cache_note: string;
  /** The grid of a point's light table (POST /api/realtime/lights). */
  light_table: LightTableShape;
  environments: string[];
  objects: string[];
  camera: RealtimeCamera;
}

export interface ReferenceRequest {
  x: Point;
  env?: string;
  rotation?: number;
  exposure?: number;
  size?: number;
}

/** The prefiltered band maps of one environment: [bands + 1][height][width][3] float32, octahedral with a one-texel border (width = height = N + 2). */
export interface EnvironmentAtlas {
  bands: number;
  width: number;
  height: number;
  values: Float32Array;
  /** The direct lights after the detail atlas: [count][6] floats at `offset` (direction, radiance x solid angle). */
  lights?: { offset: number; count: number; texels: number; fraction: number };
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
    const body = (await res.json()) as Partial<ErrorReply> | null;
    if (body && typeof body.error === "string") message = body.error;
  } catch {
    /* not JSON */
  }
  throw new ApiError(res.status, message);
}

function post<B extends PointRequest>(path: string, body: B, signal?: AbortSignal): Promise<Response> {
  return fetch(path, {
    method: "POST",
    headers: { "Content-Type": "application/json" },
    body: JSON.stringify(body),
    signal,
  }).then(check);
}

/** A refinement's answer (POST /api/preview/refine or /api/gi/refine): the image and its headers. */
async function refinedReply(r: Response): Promise<Refined> {
  const error = Number(r.headers.get("X-Matlas-Error"));
  return {
    blob: await r.blob(),
    spp: Number(r.headers.get("X-Matlas-Spp") ?? 0),
    error: Number.isFinite(error) ? error : null,
    converged: r.headers.get("X-Matlas-Converged") === "1",
    interrupted: r.headers.get("X-Matlas-Interrupted") === "1",
    denoised: r.headers.get("X-Matlas-Denoised") === "1",
  };
}

export const api = {
  model: (): Promise<ModelInfo> => fetch("api/model").then(check).then((r) => r.json()),
  preview: (x: Point, env: string, object: string, size: number, signal?: AbortSignal): Promise<Blob> =>
    post("api/preview", { x, env, object, size } satisfies PreviewRequest, signal).then((r) => r.blob()),
  previewStatus: (env: string, object: string, signal?: AbortSignal): Promise<PreviewStatus> =>
    fetch(`api/preview/status?env=${encodeURIComponent(env)}&object=${encodeURIComponent(object)}`, { signal })
      .then(check).then((r) => r.json()),
  refine: async (x: Point, env: string, object: string, seconds: number, denoise: boolean,
    signal?: AbortSignal): Promise<Refined> => {
    return refinedReply(await post("api/preview/refine", { x, env, object, seconds, denoise } satisfies RefineRequest, signal));
  },
  weights: (x: Point, top = 8): Promise<WeightsReply> =>
    post("api/weights", { x, top } satisfies WeightsRequest).then((r) => r.json()),
  interpolation: (): Promise<InterpolationData> => fetch("api/interpolation").then(check).then((r) => r.json()),
  /** The slice's PNG and its largest value (X-Matlas-Max: the top of the log colour scale). */
  slice: (x: Point, phi_d: number): Promise<{ blob: Blob; max: number }> =>
    post("api/slice", { x, phi_d } satisfies SliceRequest)
      .then(async (r) => ({ blob: await r.blob(), max: Number(r.headers.get("X-Matlas-Max") ?? "NaN") })),
  lobe: (x: Point, theta_i: number): Promise<LobeReply> =>
    post("api/lobe", { x, theta_i, samples: 181 } satisfies LobeRequest).then((r) => r.json()),
  albedo: (x: Point): Promise<AlbedoReply> => post("api/albedo", { x }).then((r) => r.json()),
  map: (body: MapRequest, signal?: AbortSignal): Promise<Blob> => post("api/map", body, signal).then((r) => r.blob()),
  /** The table of a point (or of material `material`) as MERL .binary or RGL .bsdf. */
  exportTable: (x: Point, material: number | null, format: "binary" | "bsdf" | "bsdf-spectral"): Promise<Blob> =>
    post("api/export", { x, format, ...(material === null ? {} : { material }) } satisfies ExportRequest).then((r) => r.blob()),
  /** The analytic fit's report (kept by the server for its files). */
  fit: (x: Point, material: number | null, signal?: AbortSignal, model: FitModel = "gltf"): Promise<FitReply> =>
    post("api/fit", { x, ...(material === null ? {} : { material }), ...(model === "gltf" ? {} : { model }) } satisfies FitRequest, signal)
      .then((r) => r.json()),
  fitFile: (x: Point, material: number | null, format: "gltf" | "mtlx" | "py", model: FitModel = "gltf"): Promise<Blob> =>
    post("api/fit/file", { x, format, ...(material === null ? {} : { material }), ...(model === "gltf" ? {} : { model }) } satisfies FitFileRequest)
      .then((r) => r.blob()),
  project: (file: Blob): Promise<ProjectReply> =>
    fetch("api/project", { method: "POST", headers: { "Content-Type": "application/octet-stream" }, body: file })
      .then(check)
      .then((r) => r.json()),
  /** A sample file (CSV or JSON text) fitted on the map. */
  fitSamples: (file: Blob): Promise<FitSamplesReply> =>
    fetch("api/fit-samples", { method: "POST", headers: { "Content-Type": "text/csv" }, body: file })
      .then(check)
      .then((r) => r.json()),
  /** The k directions to measure (given the samples of `file`, if any). */
  samplePlan: (k: number, file?: Blob): Promise<SamplePlanReply> =>
    fetch(`api/sample-plan?k=${k}`, { method: "POST", headers: { "Content-Type": "text/csv" }, body: file ?? "" })
      .then(check)
      .then((r) => r.json()),
  realtime: (): Promise<RealtimeInfo> => fetch("api/realtime").then(check).then((r) => r.json()),
  realtimeCoefficients: (): Promise<Float32Array> =>
    fetch("api/realtime/coefficients").then(check).then((r) => r.arrayBuffer()).then((b) => new Float32Array(b)),
  realtimeEnvironment: async (name: string): Promise<EnvironmentAtlas> => {
    const r = await fetch(`api/realtime/environment/${encodeURIComponent(name)}`).then(check);
    const shape = JSON.parse(r.headers.get("X-Matlas-Shape") ?? "{}") as Omit<EnvironmentAtlas, "values">;
    return { ...shape, values: new Float32Array(await r.arrayBuffer()) };
  },
  /** The light table of point x (float16 bits, [theta_h][theta_d][phi_d][3]). */
  realtimeLights: (x: Point): Promise<Uint16Array> =>
    post("api/realtime/lights", { x }).then((r) => r.arrayBuffer()).then((b) => new Uint16Array(b)),
  realtimeMesh: (name: string): Promise<ArrayBuffer> =>
    fetch(`api/realtime/mesh/${encodeURIComponent(name)}`).then(check).then((r) => r.arrayBuffer()),
  realtimeReference: (body: ReferenceRequest): Promise<Blob> => post("api/realtime/reference", body).then((r) => r.blob()),
  /** The scene view; `exposure` in stops or "auto" (the answer says which exposure it used). */
  gi: async (scene: string, x: Point, exposure: number | "auto", tone: string, signal?: AbortSignal): Promise<{ blob: Blob; exposure: number }> => {
    const r = await fetch(`api/gi?scene=${encodeURIComponent(scene)}&x=${x.map(String).join(",")}` +
      `&exposure=${exposure}&tone=${encodeURIComponent(tone)}`, { signal }).then(check);
    return { blob: await r.blob(), exposure: Number(r.headers.get("X-Matlas-Exposure") ?? 0) };
  },
  /** The scene view refined at rest (POST /api/gi/refine): a direct trace of the point, pass after pass. */
  giRefine: async (scene: string, x: Point, exposure: number | "auto", tone: string, seconds: number, denoise: boolean,
    signal?: AbortSignal): Promise<Refined & { exposure: number }> => {
    const r = await post("api/gi/refine", { scene, x, exposure, tone, seconds, denoise } satisfies GiRefineRequest, signal);
    return { ...(await refinedReply(r)), exposure: Number(r.headers.get("X-Matlas-Exposure") ?? 0) };
  },
  thumbnailUrl: (index: number, env: string, object: string): string =>
    `api/thumbnail/${index}?env=${encodeURIComponent(env)}&object=${encodeURIComponent(object)}`,
};
