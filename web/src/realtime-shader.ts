// The rotated-ZH shader of the real-time viewer (docs/REALTIME.md, "The browser viewer"):
//
//   radiance = sum_j lambda_j(theta_o) E_{l(j)}(d_j),   d_j = sin(alpha_j) x + cos(alpha_j) n,
//
// theta_o = acos(n . wo), x = the unit tangential part of wo. lambda is the K x T coefficient
// texture of the current map point (row t = theta_o sample at v = (t + 1/2) / T, so a linear read
// at v = theta_o / (pi/2) interpolates and clamps as the CPU reference does; column j read at its
// centre); E is the texture array of the band maps on one lat-long grid (layer l, row y at
// theta = pi y / (H - 1), column x at phi = 2 pi x / W, repeat in phi). Rotating the environment
// by beta about +y reads E at phi - beta. Output: 2^exposure, clamped, sRGB-encoded.

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

export const fragmentShader = /* glsl */ `
precision highp float;
precision highp sampler2DArray;
uniform sampler2D uCoef;       // K x T, RGB (+ unused A)
uniform sampler2D uBasis;      // K x 1: sin alpha, cos alpha, band
uniform sampler2DArray uEnv;   // W x H x (L + 1)
uniform int uCount;            // coefficients summed: (L'+1)(L'+2)/2 for the bands shown
uniform vec2 uEnvSize;         // W, H
uniform float uRotation;       // radians
uniform float uExposure;       // stops
in vec3 vWorldPos;
in vec3 vNormal;
out vec4 outColor;

const float PI = 3.14159265358979;

vec3 srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
  vec3 n = normalize(vNormal);
  vec3 wo = normalize(cameraPosition - vWorldPos);
  if (dot(n, wo) < 0.0) n = -n;  // back faces of open meshes
  float c = clamp(dot(n, wo), 0.0, 1.0);
  vec3 t = wo - c * n;
  float tl = length(t);
  if (tl < 1e-6) {
    t = abs(n.y) < 0.9 ? cross(n, vec3(0.0, 1.0, 0.0)) : cross(n, vec3(1.0, 0.0, 0.0));
    tl = length(t);
  }
  vec3 x = t / tl;
  float v = acos(c) / (0.5 * PI);
  float K = float(textureSize(uCoef, 0).x);
  vec3 sum = vec3(0.0);
  for (int j = 0; j < uCount; ++j) {
    vec3 b = texelFetch(uBasis, ivec2(j, 0), 0).xyz;
    vec3 lambda = texture(uCoef, vec2((float(j) + 0.5) / K, v)).rgb;
    vec3 d = b.x * x + b.y * n;
    float theta = acos(clamp(d.y, -1.0, 1.0));
    float phi = atan(d.z, d.x) - uRotation;
    vec2 uv = vec2(phi / (2.0 * PI) + 0.5 / uEnvSize.x, (theta / PI * (uEnvSize.y - 1.0) + 0.5) / uEnvSize.y);
    sum += lambda * texture(uEnv, vec3(uv, b.z)).rgb;
  }
  outColor = vec4(srgb(sum * exp2(uExposure)), 1.0);
}
`;
