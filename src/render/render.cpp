#include "render/render.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include "core/error.h"
#include "core/parallel.h"
#include "render/sampling.h"

namespace matlas::render {

namespace {

constexpr double kRayOffset = 1e-4;

struct Frame {
  Vec3 t, b, n;
  Vec3 to_local(const Vec3& v) const { return {t.dot(v), b.dot(v), n.dot(v)}; }
  Vec3 to_world(const Vec3& v) const { return t * v.x() + b * v.y() + n * v.z(); }
};

/// One camera sample: returns the material-independent radiance C and reports each BRDF tap
/// through tap(wi, wo, W) (local frame, W includes 1/pdf and the light).
template <class Tap>
Rgb trace_sample(const Scene& scene, const SamplingMixture& mix, SampleStream& rng, const Vec3& origin,
                 const Vec3& dir, bool* hit_object, Tap&& tap) {
  // Always draw the same numbers in the same order so every path sees the same stream.
  const double u_pick = rng.next(), u0 = rng.next(), u1 = rng.next();
  *hit_object = false;
  const std::optional<Hit> hit = scene.intersect(origin, dir);
  const SceneDescription& desc = scene.description();
  const Environment& env = scene.environment();
  if (!hit) return desc.show_environment ? env.eval_smooth(dir) : Rgb::Zero();

  Frame f;
  f.n = hit->normal;
  orthonormal_basis(f.n, f.t, f.b);
  const Vec3 wo = f.to_local(-dir);
  const Vec3 p = hit->position + hit->geometric_normal * kRayOffset;
  const Vec3& ng = hit->geometric_normal;

  if (hit->object) {
    *hit_object = true;
    if (wo.z() <= 0) return Rgb::Zero();
    Vec3 wi_world, wi;
    if (mix.picks_environment(u_pick)) {
      double pdf;
      wi_world = env.sample(u0, u1, &pdf);
      wi = f.to_local(wi_world);
    } else {
      wi = mix.sample_local(wo, u_pick, u0, u1);
      wi_world = f.to_world(wi);
    }
    if (wi.z() > 0 && wi_world.dot(ng) > 0) {
      const double pdf = mix.environment_probability() * env.pdf(wi_world) + mix.local_pdf(wo, wi);
      if (pdf > 0 && !scene.occluded(p, wi_world, 0.0)) {
        const Rgb w = env.eval(wi_world) * (wi.z() / pdf);
        if ((w > 0).any()) tap(wi.normalized(), wo, w);
      }
    }
    for (const DirectionalLight& light : desc.lights) {
      const Vec3 l = light.direction.normalized();
      const Vec3 wl = f.to_local(l);
      if (wl.z() > 0 && l.dot(ng) > 0 && !scene.occluded(p, l, 0.0)) tap(wl, wo, light.irradiance * wl.z());
    }
    return Rgb::Zero();
  }

  // Ground: Lambertian, sampled with the environment and cosine strategies only.
  const Rgb f_ground = desc.ground_albedo / kPi;
  const double ground_total = mix.environment + mix.cosine;
  const double pe = ground_total > 0 ? mix.environment / ground_total : 0.5, pc = 1.0 - pe;
  Vec3 wi_world, wi;
  if (u_pick < pe || pc <= 0) {
    double pdf;
    wi_world = env.sample(u0, u1, &pdf);
    wi = f.to_local(wi_world);
  } else {
    wi = sample_cosine(u0, u1);
    wi_world = f.to_world(wi);
  }
  Rgb radiance = Rgb::Zero();
  if (wi.z() > 0) {
    const double pdf = pe * env.pdf(wi_world) + pc * cosine_pdf(wi);
    if (pdf > 0 && !scene.occluded(p, wi_world, 0.0)) radiance += f_ground * env.eval(wi_world) * (wi.z() / pdf);
  }
  for (const DirectionalLight& light : desc.lights) {
    const Vec3 l = light.direction.normalized();
    if (l.dot(ng) > 0 && !scene.occluded(p, l, 0.0)) radiance += f_ground * light.irradiance * l.dot(ng);
  }
  return radiance;
}

/// Runs body(x, y) for every pixel, rows handed out to the workers as they become free (rows
/// cost very different amounts: sky, ground, object), with progress.
template <class PixelBody>
void for_each_pixel(const RenderSettings& settings, ProgressSink& progress, const std::string& label,
                    PixelBody&& body) {
  std::atomic<std::uint64_t> rows_done{0};
  std::mutex progress_mutex;
  const auto rows = static_cast<std::uint64_t>(settings.height);
  progress.update(label, 0, rows);
  parallel_for_each(0, static_cast<std::size_t>(settings.height), [&](std::size_t y) {
    for (int x = 0; x < settings.width; ++x) body(x, static_cast<int>(y));
    const std::uint64_t done = ++rows_done;
    std::lock_guard lock(progress_mutex);
    progress.update(label, done, rows);
  });
  progress.finish(label);
}

/// The camera samples of pixel (x, y): for sample s, the stream (seed, pixel, s) gives the
/// jitter and then the light path. Every material sees exactly these samples: this is what
/// makes an image basis linear in the BRDF (render() and render_bank() both go through here).
/// Returns the sum over samples of the material-independent radiance; tap(wi, wo, weight) is
/// called for every BRDF evaluation on the object. Adds the number of taps to `taps`.
/// Sample s of pixel (x, y): its random stream, positioned after the jitter, and camera ray.
SampleStream camera_sample(const Scene& scene, const RenderSettings& settings, int x, int y, int s, Vec3* o,
                           Vec3* d) {
  const std::uint64_t pixel =
      static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(settings.width) + static_cast<std::uint64_t>(x);
  SampleStream rng(settings.seed, pixel, static_cast<std::uint64_t>(s));
  const double jx = rng.next(), jy = rng.next();
  scene.camera_ray(x + jx, y + jy, settings.width, settings.height, o, d);
  return rng;
}

template <class Tap>
Rgb trace_pixel(const Scene& scene, const SamplingMixture& mix, const RenderSettings& settings, int x, int y, Tap&& tap,
                std::uint64_t& taps) {
  Rgb constant = Rgb::Zero();
  for (int s = 0; s < settings.spp; ++s) {
    Vec3 o, d;
    SampleStream rng = camera_sample(scene, settings, x, y, s, &o, &d);
    bool hit_object;
    constant += trace_sample(scene, mix, rng, o, d, &hit_object, [&](const Vec3& wi, const Vec3& wo, const Rgb& w) {
      tap(wi, wo, w);
      ++taps;
    });
  }
  return constant;
}

void record_stats(RenderStats* stats, const RenderSettings& settings, std::uint64_t taps,
                  std::chrono::steady_clock::time_point start) {
  if (!stats) return;
  stats->camera_samples = static_cast<std::uint64_t>(settings.width) * static_cast<std::uint64_t>(settings.height) *
                          static_cast<std::uint64_t>(settings.spp);
  stats->object_samples = taps;
  stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void RenderSettings::validate() const {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
    throw Error("render size must be between 1 and 16384 pixels, got " + std::to_string(width) + "x" +
                std::to_string(height));
  if (spp <= 0) throw Error("samples per pixel must be positive, got " + std::to_string(spp));
  mixture.validate();
}

Image render(const Scene& scene, const Material& material, const RenderSettings& settings,
             ProgressSink& progress, RenderStats* stats) {
  settings.validate();
  const auto start = std::chrono::steady_clock::now();
  const SamplingMixture& mix = settings.mixture;
  Image image(settings.width, settings.height);
  std::atomic<std::uint64_t> taps{0};
  for_each_pixel(settings, progress, "render", [&](int x, int y) {
    std::uint64_t local_taps = 0;
    Rgb reflected = Rgb::Zero();
    const Rgb constant = trace_pixel(
        scene, mix, settings, x, y,
        [&](const Vec3& wi, const Vec3& wo, const Rgb& w) { reflected += w * material.eval(wi, wo); }, local_taps);
    const Rgb sum = (constant + reflected) / static_cast<double>(settings.spp);
    float* out = image.pixel(x, y);
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(sum[c]);
    taps += local_taps;
  });
  record_stats(stats, settings, taps.load(), start);
  return image;
}

std::vector<Image> render_bank(const Scene& scene, const MaterialBank& bank, const RenderSettings& settings,
                               ProgressSink& progress, RenderStats* stats) {
  settings.validate();
  const auto start = std::chrono::steady_clock::now();
  const SamplingMixture& mix = settings.mixture;
  const int k_count = bank.count();
  if (k_count <= 0) throw Error("material bank is empty");
  std::vector<Image> images(static_cast<std::size_t>(k_count), Image(settings.width, settings.height));
  std::atomic<std::uint64_t> taps{0};
  const std::size_t values = 3 * static_cast<std::size_t>(k_count);
  for_each_pixel(settings, progress, "render basis", [&](int x, int y) {
    thread_local std::vector<double> acc, f;
    acc.assign(values, 0.0);
    f.resize(values);
    std::uint64_t local_taps = 0;
    const Rgb constant = trace_pixel(scene, mix, settings, x, y,
                                     [&](const Vec3& wi, const Vec3& wo, const Rgb& w) {
                                       bank.eval_all(wi, wo, f.data());
                                       for (std::size_t k = 0; k < values; k += 3) {
                                         acc[k] += w[0] * f[k];
                                         acc[k + 1] += w[1] * f[k + 1];
                                         acc[k + 2] += w[2] * f[k + 2];
                                       }
                                     },
                                     local_taps);
    const double inv = 1.0 / static_cast<double>(settings.spp);
    for (int k = 0; k < k_count; ++k) {
      float* out = images[static_cast<std::size_t>(k)].pixel(x, y);
      for (int c = 0; c < 3; ++c)
        out[c] = static_cast<float>((constant[c] + acc[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(c)]) * inv);
    }
    taps += local_taps;
  });
  record_stats(stats, settings, taps.load(), start);
  return images;
}

std::vector<float> object_coverage(const Scene& scene, const RenderSettings& settings) {
  settings.validate();
  std::vector<float> coverage(static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height));
  parallel_for(0, static_cast<std::size_t>(settings.height), [&](std::size_t y0, std::size_t y1) {
    for (std::size_t y = y0; y < y1; ++y)
      for (int x = 0; x < settings.width; ++x) {
        const std::uint64_t pixel = y * static_cast<std::uint64_t>(settings.width) + static_cast<std::uint64_t>(x);
        int hits = 0;
        for (int s = 0; s < settings.spp; ++s) {
          Vec3 o, d;
          camera_sample(scene, settings, x, static_cast<int>(y), s, &o, &d);
          const auto hit = scene.intersect(o, d);
          hits += hit && hit->object;
        }
        coverage[pixel] = static_cast<float>(hits) / static_cast<float>(settings.spp);
      }
  });
  return coverage;
}

}  // namespace matlas::render
