#include "render/environment.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "core/error.h"

namespace matlas::render {

Environment Environment::constant(const Rgb& radiance) {
  Environment e;
  e.constant_ = true;
  e.radiance_ = radiance;
  return e;
}

Environment::Environment(Image map, double rotation_degrees, double intensity)
    : map_(std::move(map)), rotation_(rotation_degrees * kPi / 180.0) {
  if (map_.empty()) throw Error("environment map is empty");
  for (float& x : map_.rgb) x = static_cast<float>(std::max(0.0, x * intensity));
  std::vector<double> weights(map_.pixel_count());
  for (int y = 0; y < map_.height; ++y) {
    const double sin_theta = std::sin(kPi * (y + 0.5) / map_.height);
    for (int x = 0; x < map_.width; ++x) {
      const float* p = map_.pixel(x, y);
      weights[static_cast<std::size_t>(y) * static_cast<std::size_t>(map_.width) + static_cast<std::size_t>(x)] =
          std::max({p[0], p[1], p[2]}) * sin_theta;
    }
  }
  distribution_ = Distribution2D(weights, map_.width, map_.height);
}

Environment Environment::load(const std::filesystem::path& path, double rotation_degrees, double intensity) {
  return Environment(read_image(path), rotation_degrees, intensity);
}

void Environment::to_uv(const Vec3& d, double* u, double* v) const {
  const double theta = std::acos(std::clamp(d.y(), -1.0, 1.0));
  double phi = std::atan2(d.z(), d.x()) - rotation_;
  double uu = phi / (2.0 * kPi) + 0.5;
  uu -= std::floor(uu);
  *u = std::min(uu, std::nextafter(1.0, 0.0));
  *v = std::min(theta / kPi, std::nextafter(1.0, 0.0));
}

Vec3 Environment::from_uv(double u, double v) const {
  const double theta = kPi * v, phi = 2.0 * kPi * (u - 0.5) + rotation_;
  const double s = std::sin(theta);
  return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

Rgb Environment::eval(const Vec3& d) const {
  if (constant_) return radiance_;
  double u, v;
  to_uv(d, &u, &v);
  const int x = std::clamp(static_cast<int>(u * map_.width), 0, map_.width - 1);
  const int y = std::clamp(static_cast<int>(v * map_.height), 0, map_.height - 1);
  const float* p = map_.pixel(x, y);
  return {p[0], p[1], p[2]};
}

Rgb Environment::eval_smooth(const Vec3& d) const {
  if (constant_) return radiance_;
  double u, v;
  to_uv(d, &u, &v);
  const double fx = u * map_.width - 0.5, fy = v * map_.height - 0.5;
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
  const double tx = fx - x0, ty = fy - y0;
  Rgb sum = Rgb::Zero();
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const int x = ((x0 + dx) % map_.width + map_.width) % map_.width;  // wraps in phi
      const int y = std::clamp(y0 + dy, 0, map_.height - 1);
      const double wgt = (dx ? tx : 1 - tx) * (dy ? ty : 1 - ty);
      const float* p = map_.pixel(x, y);
      sum += wgt * Rgb(p[0], p[1], p[2]);
    }
  return sum;
}

Vec3 Environment::sample(double u0, double u1, double* pdf_out) const {
  if (constant_) {
    const double z = 1.0 - 2.0 * u0, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * u1;
    *pdf_out = 1.0 / (4.0 * kPi);
    return {r * std::cos(phi), z, r * std::sin(phi)};
  }
  double u, v, pdf_uv;
  distribution_.sample(u0, u1, &u, &v, &pdf_uv);
  const double sin_theta = std::sin(kPi * v);
  *pdf_out = sin_theta > 0 ? pdf_uv / (2.0 * kPi * kPi * sin_theta) : 0.0;
  MATLAS_DCHECK(*pdf_out >= 0);
  return from_uv(u, v);
}

double Environment::pdf(const Vec3& d) const {
  if (constant_) return 1.0 / (4.0 * kPi);
  double u, v;
  to_uv(d, &u, &v);
  const double sin_theta = std::sin(kPi * v);
  return sin_theta > 0 ? distribution_.pdf(u, v) / (2.0 * kPi * kPi * sin_theta) : 0.0;
}

}  // namespace matlas::render
