#include "zonal/shade.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "render/sampling.h"

namespace matlas::zonal {

namespace {

Rgb shade_with(const ZonalBasis& basis, const ZonalCoefficients& c, const PrefilteredEnvironment& env,
               const Vec3& n, const Vec3& wo, const std::vector<double>* window, std::vector<double>& lambda) {
  const double cos_o = std::clamp(n.dot(wo), -1.0, 1.0);
  if (cos_o <= 0) return Rgb::Zero();
  Vec3 x = wo - cos_o * n;
  if (x.norm() < 1e-9) {  // normal incidence: the slice is symmetric about n, any tangent serves
    Vec3 b;
    render::orthonormal_basis(n, x, b);
  }
  x.normalize();
  c.interpolate(std::acos(cos_o), lambda);
  const std::size_t K = c.zonal_size();
  MATLAS_DCHECK_EQ(lambda.size(), 3 * c.size());
  const std::size_t terms = window ? std::min(K, window->size() * (window->size() + 1) / 2) : K;  // bands 0..L'
  Rgb sum = Rgb::Zero();
  for (std::size_t j = 0; j < terms; ++j) {
    const double a = basis.alpha(j);
    const int l = basis.band(j);
    const Rgb e = env.lookup(l, std::sin(a) * x + std::cos(a) * n);
    MATLAS_DCHECK(!window || static_cast<std::size_t>(l) < window->size(), "terms stop at the window's last band");
    const double w = window ? (*window)[static_cast<std::size_t>(l)] : 1.0;
    sum += w * Rgb(lambda[3 * j], lambda[3 * j + 1], lambda[3 * j + 2]) * e;
  }
  if (!c.lobes.empty()) {  // the sharp lobes around the mirror direction (zonal/lobes.h)
    const Vec3 r = 2.0 * cos_o * n - wo;
    for (std::size_t i = 0; i < c.lobes.size(); ++i) {
      const std::size_t j = K + i;
      sum += Rgb(lambda[3 * j], lambda[3 * j + 1], lambda[3 * j + 2]) * env.lobe_lookup(i, r);
    }
  }
  return sum;
}

void check_layout(const ZonalBasis& basis, const ZonalCoefficients& c, const PrefilteredEnvironment& env) {
  if (c.bands > basis.bands() || c.bands > env.bands())
    throw Error("zonal shading: coefficients of " + std::to_string(c.bands) + " bands, basis of " +
                std::to_string(basis.bands()) + " and environment of " + std::to_string(env.bands()));
  if (c.lobes != env.lobes())
    throw Error("zonal shading: the coefficients' " + std::to_string(c.lobes.size()) +
                " lobes differ from the environment's " + std::to_string(env.lobes().size()) + " lobe maps");
}

}  // namespace

Rgb shade_point(const ZonalBasis& basis, const ZonalCoefficients& c, const PrefilteredEnvironment& env,
                const Vec3& n, const Vec3& wo, const std::vector<double>* window) {
  check_layout(basis, c, env);
  std::vector<double> lambda;
  return shade_with(basis, c, env, n, wo, window, lambda);
}

Image shade_image(const render::Scene& scene, const ZonalBasis& basis, const ZonalCoefficients& c,
                  const PrefilteredEnvironment& env, const ShadeSettings& settings, const DirectLights* lights) {
  check_layout(basis, c, env);
  const render::SceneDescription& desc = scene.description();
  if (desc.ground || !desc.lights.empty())
    throw Error("zonal shading models environment lighting only: no ground plane or directional lights");
  if (settings.width <= 0 || settings.height <= 0 || settings.width > 16384 || settings.height > 16384 ||
      settings.subsamples < 1 || settings.subsamples > 16)
    throw Error("zonal shading: image size or subsamples out of range");
  const int shown = settings.shown_bands < 0 ? c.bands : std::min(settings.shown_bands, c.bands);
  const std::vector<double> window = band_window(shown < c.bands ? settings.reduced_window : settings.window, shown);
  Image image(settings.width, settings.height);
  const int s = settings.subsamples;
  parallel_for_each(0, static_cast<std::size_t>(settings.height), [&](std::size_t row) {
    std::vector<double> lambda;
    const int y = static_cast<int>(row);
    for (int x = 0; x < settings.width; ++x) {
      Rgb sum = Rgb::Zero();
      for (int sy = 0; sy < s; ++sy)
        for (int sx = 0; sx < s; ++sx) {
          Vec3 o, d;
          scene.camera_ray(x + (sx + 0.5) / s, y + (sy + 0.5) / s, settings.width, settings.height, &o, &d);
          const auto hit = scene.intersect(o, d);
          if (!hit) {
            if (desc.show_environment) sum += scene.environment().eval_smooth(d);
            continue;
          }
          sum += shade_with(basis, c, env, hit->normal, -d, &window, lambda);
          if (lights) sum += shade_lights(*lights->points, *lights->material, hit->normal, -d);
        }
      sum /= static_cast<double>(s * s);
      float* out = image.pixel(x, y);
      for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(sum[ch]);
    }
  });
  return image;
}

}  // namespace matlas::zonal
