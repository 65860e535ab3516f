// The three.js side of the real-time viewer: renderer, camera with orbit controls, the object
// (sphere, a served mesh, or a user's .glb) with the rotated-ZH shader (realtime-shader.ts), and
// the textures: coefficients of the current point (K x T) and the environment's octahedral band
// maps (a texture array). Renders on demand; frame times are recorded. While the user interacts
// (orbit, rotation, dragging on the map) frames are reduced: drawn at `fastScale` of the canvas's
// side into a render target with bands 0..`fastBands` only, then stretched over the canvas, so
// that the view follows the pointer even with software WebGL; the full frame (every band, full
// resolution) follows once the interaction pauses for `refineMs`. Behind the object: the
// environment itself (the detail texture's last layer), turned with it.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { GLTFLoader } from "three/examples/jsm/loaders/GLTFLoader.js";
import type { EnvironmentAtlas, RealtimeInfo } from "./api";
import {
  backgroundFragmentShader, backgroundVertexShader, bandWindow, type BandWindowName, deferredFragmentShader,
  fragmentShader, gbufferFragmentShader, maxShaderBands, maxShaderLobes, quadVertexShader, vertexShader, viewerReducedWindow,
  viewerWindow,
} from "./realtime-shader";

/** The detail atlas after the band maps (zonal::pack_detail): lobe maps, then the background. */
type DetailShape = { offset: number; lobes: number[]; layers: number; width: number; height: number };

/** RGB triples to RGBA (the alpha unused): WebGL2 cannot filter RGB float textures everywhere. */
function rgba(rgb: Float32Array, count: number, out = new Float32Array(count * 4)): Float32Array<ArrayBuffer> {
  for (let i = 0; i < count; ++i) {
    out[4 * i] = rgb[3 * i];
    out[4 * i + 1] = rgb[3 * i + 1];
    out[4 * i + 2] = rgb[3 * i + 2];
    out[4 * i + 3] = 1;
  }
  return out;
}

export class RealtimeGl {
  readonly renderer: THREE.WebGLRenderer;
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  private readonly scene = new THREE.Scene();
  private readonly material: THREE.ShaderMaterial;
  private readonly coef: THREE.DataTexture;
  private readonly coefData: Float32Array<ArrayBuffer>;
  private object: THREE.Object3D | null = null;
  private envTexture: THREE.DataArrayTexture | null = null;
  /** The current point's light table (3D, half float) and the environment's lights (2 x count). */
  private lightTable: THREE.Data3DTexture | null = null;
  private lightTableData = new Uint16Array(0);
  private lightsTexture: THREE.DataTexture | null = null;
  private lightCount = 0;
  /** Per channel, the power of lights 0..k-1 (k = 0..count): the reduced frames' scale. */
  private lightPower: number[][] = [[0, 0, 0]];
  private detailTexture: THREE.DataArrayTexture | null = null;
  /** The environment behind the object in the forward frames (hidden in the G-buffer pass). */
  private readonly backgroundMesh: THREE.Mesh;
  /** The windows over the bands shown, all of them or fewer (the server's, as its CPU reference uses). */
  readonly window: BandWindowName;
  readonly reducedWindow: BandWindowName;
  private pendingFast = false;
  private refine: ReturnType<typeof setTimeout> | null = null;
  private readonly low: THREE.WebGLRenderTarget;
  private readonly blitScene = new THREE.Scene();
  /** The full frame's G-buffer (normal, wo) and the screen quad that shades it, tile by tile. */
  private readonly gbuffer: THREE.WebGLRenderTarget;
  private readonly gbufferMaterial: THREE.ShaderMaterial;
  private readonly deferredScene = new THREE.Scene();
  private readonly blitCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  /** Milliseconds of the last full-resolution frames (render + finish), newest last. */
  readonly frameTimes: number[] = [];
  /** The same for the reduced frames drawn during interaction. */
  readonly fastFrameTimes: number[] = [];
  /** The reduced frames of map drags (drawReducedNow): when each ended and its milliseconds. */
  readonly dragFrames: { end: number; ms: number }[] = [];
  /** Side of the reduced frames relative to the canvas. */
  static readonly fastScale = 0.25;
  /** Highest band of the reduced frames (at most the bands shown); adapted to the budget. */
  fastBands = 6;
  /**
   * Lights of the reduced frames (the brightest, their power scaled to all the lights'): adapted
   * to the budget before the bands, between 16 and all of them.
   */
  fastLights = 64;
  /** Target time of a reduced frame. */
  fastBudgetMs = 40;
  /** Whether the reduced frames adapt their bands to the budget (the benchmark fixes them). */
  adaptive = true;
  /** Side of the full frame's tiles, and the time spent on tiles per animation frame (batches). */
  static readonly tileSize = 64;
  static readonly tileBudgetMs = 30;
  /** Pause of the interaction after which the full frame is drawn. */
  refineMs = 300;
  /** Highest band of the full frames. */
  private bands: number;
  /** Called after each drawn frame with performance.now() and whether it was reduced. */
  onFrame: (at: number, fast: boolean) => void = () => {};

  constructor(readonly canvas: HTMLCanvasElement, readonly info: RealtimeInfo) {
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.renderer.outputColorSpace = THREE.LinearSRGBColorSpace;  // the shader encodes sRGB itself
    this.renderer.setClearColor(0x202020, 1);
    const K = info.coefficients, T = info.theta_o_count;
    if (info.bands > maxShaderBands) throw new Error(`the server's L = ${info.bands} exceeds the shader's ${maxShaderBands}`);
    for (let j = 0, l = 0; l <= info.bands; ++l)  // the shader turns its directions by pi / (l + 1)
      for (let k = 0; k <= l; ++k, ++j)
        if (info.band[j] !== l || Math.abs(info.alpha[j] - (k * Math.PI) / (l + 1)) > 1e-6)
          throw new Error(`the server's basis differs from the shader's at coefficient ${j}`);
    // The environment maps are filtered: float32 only with OES_texture_float_linear, else half
    // floats. The coefficients are read with texelFetch (no filtering): always float32.
    const floatLinear = this.renderer.extensions.has("OES_texture_float_linear");
    this.coefData = new Float32Array(K * T * 4);
    this.coef = new THREE.DataTexture(this.coefData, K, T, THREE.RGBAFormat, THREE.FloatType);
    this.coef.magFilter = this.coef.minFilter = THREE.NearestFilter;
    this.coef.wrapS = this.coef.wrapT = THREE.ClampToEdgeWrapping;
    this.coef.needsUpdate = true;
    const steps = Array.from({ length: maxShaderBands + 1 }, (_, l) =>
      new THREE.Vector2(Math.cos(Math.PI / (l + 1)), Math.sin(Math.PI / (l + 1))));
    this.bands = info.bands;
    this.window = viewerWindow;
    this.reducedWindow = viewerReducedWindow;
    // Per theta_o sample: the (L + 1)(L + 2) / 2 rotated-ZH terms, then one weight per lobe.
    const zonalTerms = ((info.bands + 1) * (info.bands + 2)) / 2, lobes = K - zonalTerms;
    if (lobes < 0) throw new Error(`the server's ${K} coefficients are fewer than bands 0..${info.bands} need`);
    if (lobes > maxShaderLobes) throw new Error(`the server's ${lobes} lobes exceed the shader's ${maxShaderLobes}`);
    this.material = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader,
      fragmentShader,
      side: THREE.DoubleSide,
      uniforms: {
        uCoef: { value: this.coef },
        uEnv: { value: null },
        uBands: { value: info.bands },
        uStep: { value: steps },
        uWindow: { value: this.windowFactors(info.bands) },
        uEnvSide: { value: 1 },
        uDetail: { value: null },
        uDetailSide: { value: 1 },
        uLobes: { value: -1 },  // no detail texture yet
        uZonalTerms: { value: zonalTerms },
        uCameraInverse: { value: new THREE.Matrix4() },
        uBackground: { value: new THREE.Color(0x202020) },
        uRotation: { value: new THREE.Vector2(1, 0) },
        uExposure: { value: 0 },
        uLinear: { value: false },
        uLightTable: { value: null },
        uLights: { value: null },
        uLightCount: { value: 0 },
        uLightScale: { value: new THREE.Vector3(1, 1, 1) },
      },
    });
    this.material.userData.floatLinear = floatLinear;
    this.camera = new THREE.PerspectiveCamera(info.camera.fov_degrees, canvas.width / canvas.height, 0.05, 100);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", () => this.invalidate(true));
    this.low = new THREE.WebGLRenderTarget(Math.max(1, Math.round(canvas.width * RealtimeGl.fastScale)),
      Math.max(1, Math.round(canvas.height * RealtimeGl.fastScale)), { depthBuffer: true });
    this.low.texture.minFilter = this.low.texture.magFilter = THREE.LinearFilter;
    this.blitScene.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), new THREE.MeshBasicMaterial({ map: this.low.texture })));
    this.gbuffer = new THREE.WebGLRenderTarget(canvas.width, canvas.height, {
      count: 2, type: THREE.FloatType, minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, depthBuffer: true,
    });
    this.gbufferMaterial = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3, vertexShader, fragmentShader: gbufferFragmentShader, side: THREE.DoubleSide,
    });
    const deferred = new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: quadVertexShader,
      fragmentShader: deferredFragmentShader,
      depthTest: false,
      depthWrite: false,
      uniforms: {
        ...this.material.uniforms,  // the same uniform objects: one set of values
        uGNormal: { value: this.gbuffer.textures[0] },
        uGView: { value: this.gbuffer.textures[1] },
        uViewport: { value: new THREE.Vector2(canvas.width, canvas.height) },
      },
    });
    this.backgroundMesh = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), new THREE.ShaderMaterial({
      glslVersion: THREE.GLSL3,
      vertexShader: backgroundVertexShader,
      fragmentShader: backgroundFragmentShader,
      depthTest: false,
      depthWrite: false,
      uniforms: this.material.uniforms,  // the same uniform objects
    }));
    this.backgroundMesh.frustumCulled = false;
    this.backgroundMesh.renderOrder = -1;
    this.scene.add(this.backgroundMesh);
    const quad = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), deferred);
    quad.frustumCulled = false;
    this.deferredScene.add(quad);
    this.resetCamera();
    this.setObject(RealtimeGl.sphere());
  }

  /** The unit sphere (finely tessellated: its normals are interpolated across facets). */
  static sphere(): THREE.Mesh {
    return new THREE.Mesh(new THREE.SphereGeometry(1, 96, 64));
  }

  get floatLinear(): boolean {
    return this.material.userData.floatLinear as boolean;
  }

  /** The camera of the server's reference render (render::Camera's default). */
  resetCamera(): void {
    const { position: p, target: t } = this.info.camera;
    this.camera.position.set(p[0], p[1], p[2]);
    this.controls.target.set(t[0], t[1], t[2]);
    this.camera.up.set(0, 1, 0);
    this.controls.update();
    this.invalidate();
  }

  /** Coefficients of the current point: float32 [T][K][3]. */
  setCoefficients(rgb: Float32Array, interactive = false): void {
    rgba(rgb, this.info.coefficients * this.info.theta_o_count, this.coefData);
    this.coef.needsUpdate = true;
    if (interactive) this.drawReducedNow();  // a map drag: the frame follows the weights at once
    else this.invalidate();
  }

  /** uWindow's values for bands 0..L (padded to the shader's array): zonal::ShadeSettings' rule. */
  private windowFactors(L: number): number[] {
    const w = bandWindow(L < this.info.bands ? this.reducedWindow : this.window, L);
    while (w.length < maxShaderBands + 1) w.push(0);
    return w;
  }

  /** Bands 0..L of the next draw, with the window over them. */
  private useBands(L: number): void {
    this.material.uniforms.uBands.value = L;
    this.material.uniforms.uWindow.value = this.windowFactors(L);
  }

  /** The camera's inverse for the background rays (after any change of the camera). */
  private syncCamera(): void {
    this.camera.updateMatrixWorld();
    (this.material.uniforms.uCameraInverse.value as THREE.Matrix4)
      .multiplyMatrices(this.camera.matrixWorld, this.camera.projectionMatrixInverse);
  }

  setEnvironment(atlas: EnvironmentAtlas): void {
    const layers = atlas.bands + 1;
    const detail = (atlas as EnvironmentAtlas & { detail?: DetailShape }).detail;
    if (detail) {
      const count = detail.width * detail.height * detail.layers;
      const d = new THREE.DataArrayTexture(rgba(atlas.values.subarray(detail.offset), count), detail.width, detail.height,
        detail.layers);
      d.format = THREE.RGBAFormat;
      d.type = THREE.FloatType;
      if (!this.floatLinear) d.internalFormat = "RGBA16F";
      d.magFilter = d.minFilter = THREE.LinearFilter;
      d.wrapS = d.wrapT = THREE.ClampToEdgeWrapping;
      d.generateMipmaps = false;
      d.needsUpdate = true;
      this.detailTexture?.dispose();
      this.detailTexture = d;
      this.material.uniforms.uDetail.value = d;
      this.material.uniforms.uDetailSide.value = detail.width - 2;
      this.material.uniforms.uLobes.value = detail.layers - 1;
    }
    const tex = new THREE.DataArrayTexture(rgba(atlas.values, atlas.width * atlas.height * layers), atlas.width,
      atlas.height, layers);
    tex.format = THREE.RGBAFormat;
    tex.type = THREE.FloatType;
    if (!this.floatLinear) tex.internalFormat = "RGBA16F";
    tex.magFilter = tex.minFilter = THREE.LinearFilter;
    tex.wrapS = tex.wrapT = THREE.ClampToEdgeWrapping;  // the border texels continue the map
    tex.generateMipmaps = false;
    tex.needsUpdate = true;
    this.envTexture?.dispose();
    this.envTexture = tex;
    this.material.uniforms.uEnv.value = tex;
    this.material.uniforms.uEnvSide.value = atlas.width - 2;
    const lights = atlas.lights;
    this.lightsTexture?.dispose();
    this.lightsTexture = null;
    this.lightCount = 0;
    this.lightPower = [[0, 0, 0]];
    if (lights && lights.count > 0) {
      const data = new Float32Array(8 * lights.count);
      for (let i = 0; i < lights.count; ++i)
        for (let k = 0; k < 2; ++k) {
          for (let c = 0; c < 3; ++c) data[8 * i + 4 * k + c] = atlas.values[lights.offset + 6 * i + 3 * k + c];
          data[8 * i + 4 * k + 3] = 1;
        }
      for (let i = 0; i < lights.count; ++i)
        this.lightPower.push([0, 1, 2].map((c) => this.lightPower[i][c] + data[8 * i + 4 + c]));
      const l = new THREE.DataTexture(data, 2, lights.count, THREE.RGBAFormat, THREE.FloatType);
      l.magFilter = l.minFilter = THREE.NearestFilter;
      l.needsUpdate = true;
      this.lightsTexture = l;
      this.lightCount = lights.count;
    }
    this.material.uniforms.uLights.value = this.lightsTexture;
    this.syncLights();
    this.invalidate();
  }

  /**
   * Lights 0..k-1 in the next draw (k at most the environment's), scaled to the power of all; none
   * until both the environment's lights and a light table are there.
   */
  private useLights(k: number): void {
    const n = this.lightTable && this.lightsTexture ? Math.min(k, this.lightCount) : 0;
    this.material.uniforms.uLightCount.value = n;
    const all = this.lightPower[this.lightCount], part = this.lightPower[n];
    (this.material.uniforms.uLightScale.value as THREE.Vector3).set(
      ...([0, 1, 2].map((c) => (part[c] > 0 ? all[c] / part[c] : 1)) as [number, number, number]));
  }

  private syncLights(): void {
    this.useLights(this.lightCount);
  }

  /** Whether the frames include the direct lights (an environment with lights and a light table). */
  get lightsShown(): boolean {
    return !!this.lightTable && !!this.lightsTexture && this.lightCount > 0;
  }

  /**
   * The current point's light table: float16 bits [theta_h][theta_d][phi_d][3] (POST
   * /api/realtime/lights), as a 3D texture of width phi_d (repeating: period pi), height theta_d
   * and depth theta_h, filtered linearly.
   */
  setLightTable(bits: Uint16Array, interactive = false): void {
    const { theta_h: nh, theta_d: nd, phi_d: np } = this.info.light_table;
    const count = nh * nd * np;
    if (bits.length !== 3 * count) throw new Error(`a light table of ${bits.length} values, not ${3 * count}`);
    let t = this.lightTable;
    if (!t) {
      this.lightTableData = new Uint16Array(4 * count);
      t = new THREE.Data3DTexture(this.lightTableData, np, nd, nh);
      t.format = THREE.RGBAFormat;
      t.type = THREE.HalfFloatType;
      t.magFilter = t.minFilter = THREE.LinearFilter;
      t.wrapS = THREE.RepeatWrapping;
      t.wrapT = t.wrapR = THREE.ClampToEdgeWrapping;
      t.generateMipmaps = false;
      t.unpackAlignment = 1;
      this.lightTable = t;
      this.material.uniforms.uLightTable.value = t;
    }
    const data = this.lightTableData;
    for (let i = 0; i < count; ++i) {
      data[4 * i] = bits[3 * i];
      data[4 * i + 1] = bits[3 * i + 1];
      data[4 * i + 2] = bits[3 * i + 2];
      data[4 * i + 3] = 0x3c00;  // 1.0
    }
    t.needsUpdate = true;
    this.syncLights();
    if (interactive) this.joinNextReducedFrame();
    else this.invalidate();
  }

  setRotation(degrees: number, interactive = false): void {
    const beta = (degrees * Math.PI) / 180;
    (this.material.uniforms.uRotation.value as THREE.Vector2).set(Math.cos(beta), Math.sin(beta));
    this.invalidate(interactive);
  }

  setExposure(stops: number): void {
    this.material.uniforms.uExposure.value = stops;
    this.invalidate();
  }

  /** Shows bands 0..L only (a cheaper, blurrier preview). */
  setBands(L: number): void {
    this.bands = L;
    this.invalidate();
  }

  /** Replaces the object; every mesh under it gets the shader. */
  setObject(object: THREE.Object3D): void {
    if (this.object) this.scene.remove(this.object);
    object.traverse((o) => {
      if ((o as THREE.Mesh).isMesh) (o as THREE.Mesh).material = this.material;
    });
    this.object = object;
    this.scene.add(object);
    this.invalidate();
  }

  /** A served mesh: counts, positions, normals, triangles (docs/API.md). */
  static meshFromBuffer(buffer: ArrayBuffer): THREE.Mesh {
    const [v, t] = new Uint32Array(buffer, 0, 2);
    const g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.BufferAttribute(new Float32Array(buffer, 8, 3 * v), 3));
    g.setAttribute("normal", new THREE.BufferAttribute(new Float32Array(buffer, 8 + 12 * v, 3 * v), 3));
    g.setIndex(new THREE.BufferAttribute(new Uint32Array(buffer, 8 + 24 * v, 3 * t), 1));
    return new THREE.Mesh(g);
  }

  /** A user's .glb, centred and scaled into the unit sphere as the renderer places meshes. */
  static async meshFromGlb(buffer: ArrayBuffer): Promise<THREE.Object3D> {
    const gltf = await new GLTFLoader().parseAsync(buffer, "");
    const root = gltf.scene;
    root.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(root);
    const centre = box.getCenter(new THREE.Vector3());
    let radius = 0;
    const p = new THREE.Vector3();
    root.traverse((o) => {
      const m = o as THREE.Mesh;
      if (!m.isMesh) return;
      if (!m.geometry.getAttribute("normal")) m.geometry.computeVertexNormals();
      const pos = m.geometry.getAttribute("position");
      for (let i = 0; i < pos.count; ++i) radius = Math.max(radius, p.fromBufferAttribute(pos, i).applyMatrix4(m.matrixWorld).distanceTo(centre));
    });
    const group = new THREE.Group();
    group.add(root);
    root.position.sub(centre);
    group.scale.setScalar(1 / (radius || 1));
    return group;
  }

  /**
   * Schedules the view's update: a reduced frame at once (within this animation frame), then,
   * once nothing has changed for `refineMs` (0 for a non-interactive change), the full frame in
   * tiles, a few per animation frame, so that the page stays responsive: a new change cancels
   * the tiles not yet drawn and starts over.
   */
  invalidate(interactive = false): void {
    this.tiles = null;
    // This frame draws the newest state: a drag's paced or wanted reduced frame would only repeat
    // it and restart the full frame (after a drag, the coefficients at rest come here).
    if (this.pacedDraw) clearTimeout(this.pacedDraw);
    this.pacedDraw = null;
    this.reducedWanted = false;
    if (!this.pendingFast) {
      this.pendingFast = true;
      requestAnimationFrame(() => {
        this.pendingFast = false;
        this.draw(true);
      });
    }
    this.refineAfter(interactive ? this.refineMs : 0);
  }

  /** The full frame's tiles start `ms` from now, unless another change comes first. */
  private refineAfter(ms: number): void {
    if (this.refine) clearTimeout(this.refine);
    this.refine = setTimeout(() => {
      this.refine = null;
      this.startRefinement();
    }, ms);
  }

  /**
   * A change during a map drag (the point's light table arriving): drawn by the drag's next
   * reduced frame (drawReducedNow, paced), not by one more now: a frame waits for the GPU, and a
   * software GPU's reduced frame (60 ms on the 2-core VM) per light table doubled the frames of a
   * drag and held the page (docs/BENCHMARKS.md, "Real-time viewer"). The tiles under way stop; the
   * full frame follows once the drag has been still for `refineMs`.
   */
  private joinNextReducedFrame(): void {
    this.tiles = null;
    this.refineAfter(this.refineMs);
  }

  /** The end and length of the last reduced frame of a map drag (pacing, below). */
  private lastReduced = { end: -Infinity, ms: 0 };
  private pacedDraw: ReturnType<typeof setTimeout> | null = null;
  /** A reduced frame over this many ms is slow (longer than an animation frame): paced. */
  static readonly slowFrameMs = 17;
  /** After a slow reduced frame of t ms, the next is drawn no sooner than this x t ms later: a
   *  software GPU then takes a seventh of the cores during a drag (3, a quarter, left the
   *  1000-material drag's preview median 20-30 ms higher on the 2-core VM, docs/BENCHMARKS.md
   *  "The map drag on a slow day"). */
  static readonly pacing = 6;
  /** A drag's reduced frame seen finished more than this many ms after the fence was last seen
   *  unsignalled has no measured time (drawReducedNow). */
  static readonly lateLookMs = 50;

  /**
   * Draws a reduced frame now (map drags), one at a time, and learns when the GPU has finished it
   * from a fence polled between tasks, so that the page's main thread is not held while a
   * software GPU draws (a wait in readPixels held it for the whole frame: the 1000-material drag's
   * preview median 130-179 -> 92-104 ms on the 2-core VM, docs/BENCHMARKS.md "Real-time viewer").
   * Its time adapts the bands. Paced when frames are slow: after a frame of t ms over an animation
   * frame the next (with the newest coefficients) waits 6t, so a software GPU on a small machine
   * (30-70 ms a frame, on the cores the page and the server use) takes a seventh of the cores and
   * the reference render keeps up with the pointer while the map is dragged; a GPU's frames of a
   * few ms are not held back.
   */
  drawReducedNow(): void {
    if (this.refine) clearTimeout(this.refine);
    this.refine = null;
    this.tiles = null;
    const { end, ms: last } = this.lastReduced;
    const wait = last > RealtimeGl.slowFrameMs ? end + RealtimeGl.pacing * last - performance.now() : 0;
    if (wait > 0) {
      this.pacedDraw ??= setTimeout(() => {
        this.pacedDraw = null;
        this.drawReducedNow();
      }, wait);
      return;
    }
    if (this.reducedInFlight) {  // one frame at a time: the newest coefficients go into the next
      this.reducedWanted = true;
      return;
    }
    if (!this.envTexture) return;
    const start = performance.now();
    this.submit(true);
    const gl = this.renderer.getContext() as WebGL2RenderingContext;  // three.js renders with WebGL2 only
    const sync = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl.flush();
    this.reducedInFlight = true;
    // Polled, not waited for: the page's main thread stays free (the preview's image, the pointer)
    // while a software GPU draws on the cores.
    let looked = start;  // when the fence was last seen unsignalled
    const poll = () => {
      const now = performance.now();
      if (sync && gl.clientWaitSync(sync, 0, 0) === gl.TIMEOUT_EXPIRED) {
        looked = now;
        setTimeout(poll, 2);
        return;
      }
      if (sync) gl.deleteSync(sync);
      this.reducedInFlight = false;
      const end = now;
      // Seen finished long after the last look (the page was held by other work: a full frame
      // drawn at once, a long task), the frame's time is not known: it adapts nothing, and the
      // pacing counts it as long as the last one measured (an 11 s wait behind a full frame would
      // otherwise hold the next reduced frame for a minute).
      let ms: number;
      if (end - looked <= RealtimeGl.lateLookMs) {
        ms = this.finished(true, start, end);
      } else {
        ms = Math.min(end - start, this.lastReduced.ms || this.fastBudgetMs);
        this.record(this.fastFrameTimes, ms, end, true);
      }
      this.lastReduced = { end, ms };
      this.dragFrames.push(this.lastReduced);
      if (this.dragFrames.length > 1000) this.dragFrames.shift();
      this.refineAfter(this.refineMs);
      if (this.reducedWanted) {
        this.reducedWanted = false;
        this.drawReducedNow();
      }
    };
    setTimeout(poll, 0);
  }
  private reducedInFlight = false;
  private reducedWanted = false;

  private tiles: { x: number; y: number }[] | null = null;
  private refinementMs = 0;

  /** The full frame, tile by tile over the reduced one, centre first. */
  private startRefinement(): void {
    if (!this.envTexture) return;
    const t = RealtimeGl.tileSize, w = this.canvas.width, h = this.canvas.height;
    const tiles: { x: number; y: number }[] = [];
    for (let y = 0; y < h; y += t) for (let x = 0; x < w; x += t) tiles.push({ x, y });
    const d = (p: { x: number; y: number }) => (p.x + t / 2 - w / 2) ** 2 + (p.y + t / 2 - h / 2) ** 2;
    tiles.sort((a, b) => d(a) - d(b));
    this.tiles = tiles;
    this.refinementMs = 0;
    let gbuffer = false;
    let batch = 1;
    const step = () => {
      if (this.tiles !== tiles) return;  // cancelled by a change
      const start = performance.now();
      if (!gbuffer) {
        this.fillGbuffer();
        gbuffer = true;
      }
      // A batch of tiles, then one wait for the GPU: the batch is sized from the previous one's
      // rate to fit the budget (a wait per tile costs more than small tiles do under load).
      const count = Math.min(tiles.length, batch);
      for (let i = 0; i < count; ++i) this.drawTile(tiles.pop()!);
      const gl = this.renderer.getContext();
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));  // waits for the batch
      const ms = performance.now() - start;
      // At most 4 tiles: the next tiles may cost far more than the last ones (background ones
      // are cheap), and a batch cannot be interrupted.
      batch = Math.max(1, Math.min(4, 2 * count, Math.floor((count * RealtimeGl.tileBudgetMs) / Math.max(ms, 1))));
      this.refinementMs += ms;
      if (tiles.length) {
        requestAnimationFrame(step);
        return;
      }
      this.tiles = null;
      this.record(this.frameTimes, this.refinementMs, performance.now(), false);
    };
    requestAnimationFrame(step);
  }

  /** Rasterises the object into the G-buffer: normal and wo per pixel, alpha 0 outside. */
  private fillGbuffer(): void {
    const clear = this.renderer.getClearColor(new THREE.Color()), alpha = this.renderer.getClearAlpha();
    this.renderer.setClearColor(0x000000, 0);
    this.scene.overrideMaterial = this.gbufferMaterial;
    this.backgroundMesh.visible = false;
    try {
      this.renderer.setRenderTarget(this.gbuffer);
      this.renderer.render(this.scene, this.camera);
    } finally {
      this.renderer.setRenderTarget(null);
      this.scene.overrideMaterial = null;
      this.backgroundMesh.visible = true;
      this.renderer.setClearColor(clear, alpha);
    }
  }

  /** One tile of the full frame onto the canvas (its drawing buffer is preserved). */
  private drawTile(tile: { x: number; y: number }): void {
    if (!this.envTexture) return;
    const t = RealtimeGl.tileSize;
    this.useBands(this.bands);
    this.useLights(this.lightCount);
    this.syncCamera();
    this.renderer.setScissorTest(true);
    this.renderer.setScissor(tile.x, tile.y, t, t);
    this.renderer.render(this.deferredScene, this.blitCamera);
    this.renderer.setScissorTest(false);
  }

  /**
   * The full frame at size x size as float RGBA, rows from the top: RGB = 2^exposure times the
   * radiance, neither clamped nor encoded (what POST /api/realtime/reference/radiance answers).
   */
  radiance(size: number): Float32Array {
    const target = new THREE.WebGLRenderTarget(size, size, { type: THREE.FloatType, depthBuffer: true });
    const aspect = this.camera.aspect;
    this.camera.aspect = 1;
    this.camera.updateProjectionMatrix();
    this.useBands(this.bands);
    this.useLights(this.lightCount);
    this.syncCamera();
    this.material.uniforms.uLinear.value = true;
    const pixels = new Float32Array(size * size * 4);
    try {
      this.renderer.setRenderTarget(target);
      this.renderer.render(this.scene, this.camera);
      this.renderer.readRenderTargetPixels(target, 0, 0, size, size, pixels);
    } finally {
      this.renderer.setRenderTarget(null);
      this.material.uniforms.uLinear.value = false;
      this.camera.aspect = aspect;
      this.camera.updateProjectionMatrix();
      target.dispose();
    }
    const out = new Float32Array(pixels.length);
    for (let y = 0; y < size; ++y) out.set(pixels.subarray((size - 1 - y) * size * 4, (size - y) * size * 4), y * size * 4);
    return out;
  }

  private record(times: number[], ms: number, end: number, fast: boolean): void {
    times.push(ms);
    if (times.length > 1000) times.shift();

    this.onFrame(end, fast);
  }

  /**
   * Draws a whole frame now, reduced (`fast`) or full, and waits for it; returns the
   * milliseconds taken. A reduced frame adapts `fastBands` to stay within `fastBudgetMs`.
   */
  draw(fast = false): number {
    if (!this.envTexture) return 0;
    if (!fast) this.tiles = null;  // a full frame supersedes the tiles
    const start = performance.now();
    this.submit(fast);
    const gl = this.renderer.getContext();
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));  // waits for the frame
    return this.finished(fast, start, performance.now());
  }

  /** The commands of a reduced (`fast`) or full frame, not waited for. */
  private submit(fast: boolean): void {
    this.useBands(fast ? Math.min(this.bands, this.fastBands) : this.bands);
    this.useLights(fast ? this.fastLights : this.lightCount);
    this.syncCamera();
    if (fast) {
      this.renderer.setRenderTarget(this.low);
      this.renderer.render(this.scene, this.camera);
      this.renderer.setRenderTarget(null);
      this.renderer.render(this.blitScene, this.blitCamera);
    } else {
      this.renderer.render(this.scene, this.camera);
    }
  }

  /** A frame submitted at `start` has finished at `end`: its time adapts the reduced frames and is recorded. */
  private finished(fast: boolean, start: number, end: number): number {
    const ms = end - start;
    if (fast && this.adaptive && this.lightCount > 0 &&
      (ms > this.fastBudgetMs ? this.fastLights > 16 : ms < 0.7 * this.fastBudgetMs && this.fastLights < this.lightCount)) {
      // The lights first: halved over the budget (down to 16), doubled well under it.
      this.fastLights = ms > this.fastBudgetMs ? Math.max(16, this.fastLights >> 1) : Math.min(this.lightCount, 2 * this.fastLights);
    } else if (fast && this.adaptive) {
      // Over the budget: the most bands whose terms, (L' + 1)(L' + 2) / 2, fit it at this frame's
      // rate per term (the cost is about proportional to them, plus the rasterisation). Well
      // under it: one band more.
      const terms = (b: number) => ((b + 1) * (b + 2)) / 2;
      const current = Math.min(this.fastBands, this.bands);
      let next = current;
      if (ms > this.fastBudgetMs) {
        const fit = (terms(current) * this.fastBudgetMs) / ms;
        while (next > 1 && terms(next) > fit) --next;
      } else if (ms < 0.7 * this.fastBudgetMs && current < this.bands) {
        ++next;
      }
      this.fastBands = next;
    }
    this.record(fast ? this.fastFrameTimes : this.frameTimes, ms, end, fast);
    return ms;
  }
}
