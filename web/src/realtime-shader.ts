// The rotated-ZH shader of the real-time viewer (docs/REALTIME.md, "The browser viewer"):
//
//   radiance = sum_{l <= L'} sum_{k <= l} lambda_lk(theta_o) E_l(R d_lk),
//   d_lk = sin(alpha_lk) x + cos(alpha_lk) n,   alpha_lk = k pi / (l + 1),
//
// theta_o = acos(n . wo), x = the unit tangential part of wo, R the environment's rotation by
// -beta about +y (applied once to n and x: d is linear in them). No trigonometry per term: the
// directions of band l are n and x turned in steps of pi / (l + 1) (uStep[l] = cos, sin of the
// step), and the band maps E_l are octahedral (zonal/shader_layout.h: one texture array, one
// texel of border continuing the map across its edges, so bilinear filtering is seamless).
// lambda is the K x T coefficient texture of the current map point, row t = theta_o sample
// (t + 1/2) (pi/2) / T: two texel reads per term, interpolated in float with the weight computed
// once per pixel (clamped at the ends), as the CPU reference does. Band l's terms are weighted
// by uWindow[l] (zonal/window.h, the window over the bands shown: computed by bandWindow below
// with the same formulas as the CPU reference). Then the sharp lobes (zonal/lobes.h): lobe i's
// weight is column K + i of the coefficient texture, its map layer i of the detail texture
// (octahedral, finer), read at the mirror direction r = 2 (n . wo) n - wo. The detail texture's
// last layer is the environment itself (Environment::eval_smooth): the background where no
// object covers the pixel. Then the direct lights (src/zonal/light_split.h): the environment's
// brightest texels, which the band and lobe maps leave out, each a point (uLights: direction and
// radiance x solid angle, in the unrotated map's frame) shaded with the point's light table
// (uLightTable, src/zonal/light_table.h: a 3D texture over phi_d, theta_d and theta_h in MERL's
// square-root coordinate, read trilinearly: phi_d repeats with period pi, the thetas clamp), at
// the Rusinkiewicz angles of (wi, wo) as src/brdf/merl_grid.cpp computes them. Output:
// 2^exposure, clamped, sRGB-encoded (or, with uLinear, the radiance times 2^exposure as is, for
// float targets).

/** Highest band the shader's step table holds. */
export const maxShaderBands = 32;
/** Most lobes the shader sums. */
export const maxShaderLobes = 8;

export type BandWindowName = "none" | "hann" | "lanczos" | "gauss" | "taper";

/**
 * The viewer's windows (src/server/realtime.h: kRealtimeWindow, kRealtimeReducedWindow, which the
 * server's CPU reference uses): none with every band (the coefficients carry a window per view
 * angle, src/zonal/ring_limit.h), Hann with fewer (the bands slider, the reduced frames while
 * moving).
 */
export const viewerWindow: BandWindowName = "none";
export const viewerReducedWindow: BandWindowName = "hann";

/**
 * w_0..w_L of a window over bands 0..L (src/zonal/window.cpp's formulas): none 1; hann
 * cos^2(pi l / (2 (L + 1))); lanczos sinc(pi l / (L + 1)); gauss exp(-l (l + 1) / (2 s^2)),
 * s = (L + 1) / 2.5; taper 1 up to h = (L + 1) / 2, then cos^2(pi (l - h) / (2 (L + 1 - h))).
 * w_0 = 1 always.
 */
export function bandWindow(name: BandWindowName, L: number): number[] {
  const n = L + 1;
  return Array.from({ length: n }, (_, l) => {
    if (l === 0) return 1;
    switch (name) {
      case "hann": return Math.cos((Math.PI * l) / (2 * n)) ** 2;
      case "lanczos": return Math.sin((Math.PI * l) / n) / ((Math.PI * l) / n);
      case "gauss": return Math.exp((-l * (l + 1)) / (2 * (n / 2.5) ** 2));
      case "taper": return l <= n / 2 ? 1 : Math.cos((Math.PI * (l - n / 2)) / (2 * (n - n / 2))) ** 2;
      default: return 1;
    }
  });
}

export const vertexShader = /* glsl */ `
out vec3 vWorldPos;
out vec3 vNormal;
void main() {
  vec4 wp = modelMatrix * vec4(position, 1.0);
  vWorldPos = wp.xyz;
  vNormal = normalize(mat3(modelMatrix) * normal);
  gl_Position = projectionMatrix * viewMatrix * wp;
}
`;

// Uniforms and the shading of one point, shared by the forward and the deferred shaders.
const shading = /* glsl */ `
precision highp float;
precision highp sampler2DArray;
precision highp sampler3D;
uniform sampler2D uCoef;       // K x T, RGB (+ unused A), read with texelFetch
uniform sampler2DArray uEnv;   // (N + 2) x (N + 2) x (L + 1), octahedral with a border
uniform int uBands;            // L': bands 0..L' are summed
uniform vec2 uStep[${maxShaderBands + 1}];  // cos, sin of pi / (l + 1)
uniform float uWindow[${maxShaderBands + 1}];  // band l's weight (the window over bands 0..L')
uniform float uEnvSide;        // N
uniform sampler2DArray uDetail;  // lobe maps 0..M-1, then the background; octahedral with a border
uniform float uDetailSide;     // its N
uniform int uLobes;            // M (0: no detail texture)
uniform int uZonalTerms;       // K of the coefficient texture: lobe i is column K + i
uniform vec2 uRotation;        // cos, sin of the environment's rotation
uniform float uExposure;       // stops
uniform bool uLinear;          // output 2^exposure radiance as is (float targets: the tests' comparison)
uniform sampler3D uLightTable; // phi_d x theta_d x theta_h, RGB (+ unused A)
uniform sampler2D uLights;     // 2 x count: direction, then radiance x solid angle
uniform int uLightCount;       // lights 0..count-1 (the brightest first); 0: none, or no light table yet
uniform vec3 uLightScale;      // all the lights' power over that of the first uLightCount (reduced frames)
out vec4 outColor;

const float PI = 3.14159265358979;

// The direct lights at a point of normal n seen from wo (unrotated frame, unit vectors).
vec3 directLights(vec3 n, vec3 wo) {
  vec3 sum = vec3(0.0);
  for (int i = 0; i < uLightCount; ++i) {
    vec3 wi = texelFetch(uLights, ivec2(0, i), 0).xyz;
    float ci = dot(n, wi);
    if (ci <= 0.0) continue;
    vec3 h = normalize(wi + wo);
    vec3 b = cross(n, h);  // the axis of theta_h's turn (MERL: z rotated by phi_h)
    float bl = length(b);
    b = bl > 1e-7 ? b / bl : normalize(abs(n.y) < 0.9 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
    vec3 t = cross(b, h);
    float thetaH = acos(clamp(dot(h, n), -1.0, 1.0));
    float thetaD = acos(clamp(dot(wi, h), -1.0, 1.0));
    float phiD = atan(dot(wi, b), dot(wi, t));
    vec3 f = texture(uLightTable, vec3(phiD / PI, thetaD / (0.5 * PI), sqrt(thetaH / (0.5 * PI)))).rgb;
    sum += f * texelFetch(uLights, ivec2(1, i), 0).rgb * ci;
  }
  return uLightScale * sum;
}

vec3 srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// Texture coordinates of direction d on octahedral maps of side N (y up).
vec2 octahedral(vec3 d, float side) {
  vec2 p = d.xz / (abs(d.x) + abs(d.y) + abs(d.z));
  vec2 s = vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
  p = d.y < 0.0 ? (1.0 - abs(p.yx)) * s : p;
  return (p * (0.5 * side) + (0.5 * side + 1.0)) / (side + 2.0);
}

// The lookup direction of the rotated environment: phi - beta.
vec3 unrotate(vec3 d) {
  return vec3(uRotation.x * d.x + uRotation.y * d.z, d.y, uRotation.x * d.z - uRotation.y * d.x);
}

// Radiance towards wo of a point with normal n (both unit, dot(n, wo) >= 0), as displayed.
vec4 shade(vec3 n, vec3 wo) {
  float c = clamp(dot(n, wo), 0.0, 1.0);
  vec3 r = unrotate(2.0 * c * n - wo);  // the mirror direction: the lobes' axis
  vec3 t = wo - c * n;
  float tl = length(t);
  if (tl < 1e-6) {
    t = abs(n.y) < 0.9 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0));
    tl = length(t);
  }
  vec3 x = unrotate(t / tl);
  n = unrotate(n);
  int T = textureSize(uCoef, 0).y;
  float tf = clamp(acos(c) / (0.5 * PI) * float(T) - 0.5, 0.0, float(T - 1));
  int t0 = int(tf);
  int t1 = min(t0 + 1, T - 1);
  float f = tf - float(t0);
  vec3 sum = vec3(0.0);
  int j = 0;
  for (int l = 0; l <= uBands; ++l) {
    vec2 st = uStep[l];
    vec2 cs = vec2(1.0, 0.0);  // cos, sin of alpha_lk
    float layer = float(l);
    vec3 band = vec3(0.0);
    for (int k = 0; k <= l; ++k) {
      vec3 lambda = mix(texelFetch(uCoef, ivec2(j, t0), 0).rgb, texelFetch(uCoef, ivec2(j, t1), 0).rgb, f);
      band += lambda * texture(uEnv, vec3(octahedral(cs.y * x + cs.x * n, uEnvSide), layer)).rgb;
      cs = vec2(cs.x * st.x - cs.y * st.y, cs.y * st.x + cs.x * st.y);
      ++j;
    }
    sum += uWindow[l] * band;
  }
  vec2 ro = octahedral(r, uDetailSide);
  for (int i = 0; i < uLobes; ++i) {
    int col = uZonalTerms + i;
    vec3 w = mix(texelFetch(uCoef, ivec2(col, t0), 0).rgb, texelFetch(uCoef, ivec2(col, t1), 0).rgb, f);
    sum += w * texture(uDetail, vec3(ro, float(i))).rgb;
  }
  sum += directLights(n, c * n + sqrt(max(0.0, 1.0 - c * c)) * x);  // wo, unrotated
  sum *= exp2(uExposure);
  return vec4(uLinear ? sum : srgb(sum), 1.0);
}
`;

// The environment seen along a camera ray d (world), as displayed.
const backgroundShading = /* glsl */ `
uniform mat4 uCameraInverse;   // camera.matrixWorld * projectionMatrixInverse
uniform vec3 uBackground;      // without a detail texture: a plain colour
vec4 background(vec2 ndc) {
  if (uLobes < 0) return vec4(uBackground, 1.0);
  vec4 p = uCameraInverse * vec4(ndc, 1.0, 1.0);
  vec4 q = uCameraInverse * vec4(ndc, -1.0, 1.0);
  vec3 d = normalize(p.xyz / p.w - q.xyz / q.w);
  vec3 e = texture(uDetail, vec3(octahedral(unrotate(d), uDetailSide), float(uLobes))).rgb * exp2(uExposure);
  return vec4(uLinear ? e : srgb(e), 1.0);
}
`;

export const fragmentShader = /* glsl */ `
${shading}in vec3 vWorldPos;
in vec3 vNormal;

void main() {
  vec3 n = normalize(vNormal);
  vec3 wo = normalize(cameraPosition - vWorldPos);
  if (dot(n, wo) < 0.0) n = -n;  // back faces of open meshes
  outColor = shade(n, wo);
}
`;

// Deferred shading of the full frame's tiles: the object is rasterised once into a G-buffer
// (unit normal facing the viewer, and wo; alpha 0 where there is no object), then each tile is a
// screen-filling quad (scissored) that shades the G-buffer's texels: the mesh is not drawn again
// per tile.
export const gbufferFragmentShader = /* glsl */ `
precision highp float;
in vec3 vWorldPos;
in vec3 vNormal;
layout(location = 0) out vec4 gNormal;
layout(location = 1) out vec4 gView;
void main() {
  vec3 n = normalize(vNormal);
  vec3 wo = normalize(cameraPosition - vWorldPos);
  if (dot(n, wo) < 0.0) n = -n;
  gNormal = vec4(n, 1.0);
  gView = vec4(wo, 1.0);
}
`;

export const quadVertexShader = /* glsl */ `
void main() {
  gl_Position = vec4(position.xy, 0.0, 1.0);
}
`;

export const deferredFragmentShader = /* glsl */ `
${shading}${backgroundShading}uniform sampler2D uGNormal;
uniform sampler2D uGView;
uniform vec2 uViewport;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 n = texelFetch(uGNormal, p, 0);
  if (n.a == 0.0) {  // a branch, not a select: background pixels skip the sum
    outColor = background(gl_FragCoord.xy / uViewport * 2.0 - 1.0);
    return;
  }
  outColor = shade(n.xyz, texelFetch(uGView, p, 0).xyz);
}
`;

// The background of the forward frames: a screen quad at the far plane, drawn first.
export const backgroundVertexShader = /* glsl */ `
out vec2 vNdc;
void main() {
  vNdc = position.xy;
  gl_Position = vec4(position.xy, 1.0, 1.0);
}
`;

export const backgroundFragmentShader = /* glsl */ `
${shading}${backgroundShading}in vec2 vNdc;
void main() {
  outColor = background(vNdc);
}
`;
