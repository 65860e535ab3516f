#include "render/render.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "render/adaptive_sampling.h"
#include "render/pixel_sampler.h"
#include "render/sampling.h"

namespace matlas::render {

namespace {

constexpr double kRayOffset = 1e-4;
/// RenderSettings::grazing_samples: pixels whose centre sees the object at cos(theta_o) below
/// this take more camera samples, in proportion to 1 / cos(theta_o).
constexpr double kGrazingCosine = 0.5;

struct Frame {
  Vec3 t, b, n;
  Vec3 to_local(const Vec3& v) const { return {t.dot(v), b.dot(v), n.dot(v)}; }
  Vec3 to_world(const Vec3& v) const { return t * v.x() + b * v.y() + n * v.z(); }
};

/// The random choices of one camera sample after its jitter: the object's strategy (the
/// environment, or u for SamplingMixture::sample_local), the ground's (environment or cosine,
/// with the environment's probability) and the direction's two numbers.
struct Draw {
  bool environment = false;
  double pick = 0;
  bool ground_environment = false;
  double ground_environment_probability = 0;
  double u0 = 0, u1 = 0;
  /// Sampler::light_and_lobe: an environment sample (e0, e1) besides the lobe sample (u0, u1),
  /// each tap weighted by half (two taps per camera sample; the density counts both).
  bool both = false;
  double e0 = 0, e1 = 0;
  bool power = false;  ///< RenderSettings::power_heuristic
  double jx = 0, jy = 0;  ///< the camera sample's position in its pixel
};

/// The weight of a tap divided by f L cos: the environment technique's density share a and the
/// lobes' b (the density's two parts), `own` the one that drew it. Balance: 1 / (a + b); power:
/// own / (a^2 + b^2) (Veach's multi-sample power heuristic, each technique's count folded in).
double mis_weight(bool power, double a, double b, double own) {
  MATLAS_DCHECK(a >= 0 && b >= 0 && a + b > 0, "densities of a drawn direction");
  return power ? own / (a * a + b * b) : 1.0 / (a + b);
}

/// The independent sampler's draw: three numbers of the sample's stream.
Draw independent_draw(const SamplingMixture& mix, SampleStream& rng) {
  // Always draw the same numbers in the same order so every path sees the same stream.
  Draw d;
  d.pick = rng.next(), d.u0 = rng.next(), d.u1 = rng.next();
  d.environment = mix.picks_environment(d.pick);
  const double ground_total = mix.environment + mix.cosine;
  d.ground_environment_probability = ground_total > 0 ? mix.environment / ground_total : 0.5;
  d.ground_environment = d.pick < d.ground_environment_probability || d.ground_environment_probability >= 1.0;
  return d;
}

/// One camera sample: returns the material-independent radiance C and reports each BRDF tap
/// through tap(wi, wo, W) (local frame, W includes 1/pdf and the light).
/// A control variate of one pixel's samples (render/control_variate.h): the function, and where
/// the grid serves the pixel, its smooth integral interpolated at a sample's position.
struct PixelControl {
  const ControlVariate* variate = nullptr;
  const ControlGrid::Cell* cell = nullptr;  ///< the grid's cell of this pixel (none: evaluate)
  const ControlGrid* grid = nullptr;
  Rgb* sum = nullptr;  ///< where the samples add G minus their g terms
  Rgb smooth(const Draw& draw, const Vec3& n, const Vec3& wo) const {
    if (!cell) return variate->smooth_integral(n, wo);
    const int s = cell->subdivisions;
    const double u = draw.jx * s, v = draw.jy * s;
    const int i = std::min(static_cast<int>(u), s - 1), j = std::min(static_cast<int>(v), s - 1);
    const double fx = u - i, fy = v - j;
    const Rgb* p = &grid->values[cell->offset + static_cast<std::size_t>(j) * static_cast<std::size_t>(s + 1) + static_cast<std::size_t>(i)];
    const std::size_t row = static_cast<std::size_t>(s) + 1;
    return (1 - fy) * ((1 - fx) * p[0] + fx * p[1]) + fy * ((1 - fx) * p[row] + fx * p[row + 1]);
  }
};

template <class Tap>
Rgb trace_sample(const Scene& scene, const SamplingMixture& mix, const Draw& draw, const Vec3& origin,
                 const Vec3& dir, bool* hit_object, Tap&& tap, const PixelControl& control = {}) {
  const double u0 = draw.u0, u1 = draw.u1;
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
    const double share = draw.both ? 0.5 : 1.0;
    // With a control variate: G here, minus g at every tap (render/control_variate.h).
    const ControlVariate* variate = control.variate;
    Rgb controlled = Rgb::Zero();
    if (variate) controlled = control.smooth(draw, f.n, -dir) + variate->sharp_integral(f.n, -dir);
    const auto tap_direction = [&](const Vec3& wi_world, const Vec3& wi, bool environment) {
      if (variate && (environment || wi.z() > 0)) {
        const double a = mix.environment_probability() * env.pdf(wi_world), b = wi.z() > 0 ? mix.local_pdf(wo, wi) : 0.0;
        if (a + b > 0)
          controlled -= env.eval(wi_world) * variate->eval(wi.normalized(), wo) *
                        (share * mis_weight(draw.power, a, b, environment ? a : b));
      }
      if (wi.z() <= 0 || wi_world.dot(ng) <= 0) return;
      const double a = mix.environment_probability() * env.pdf(wi_world), b = mix.local_pdf(wo, wi);
      if (a + b > 0 && !scene.occluded(p, wi_world, 0.0)) {
        const Rgb w = env.eval(wi_world) * (share * wi.z() * mis_weight(draw.power, a, b, environment ? a : b));
        if ((w > 0).any()) tap(wi.normalized(), wo, w);
      }
    };
    if (draw.environment || draw.both) {
      double pdf;
      const Vec3 wi_world = draw.both ? env.sample(draw.e0, draw.e1, &pdf) : env.sample(u0, u1, &pdf);
      tap_direction(wi_world, f.to_local(wi_world), true);
    }
    if (!draw.environment) {
      const Vec3 wi = mix.sample_local(wo, draw.pick, u0, u1);
      tap_direction(f.to_world(wi), wi, false);
    }
    for (const DirectionalLight& light : desc.lights) {
      const Vec3 l = light.direction.normalized();
      const Vec3 wl = f.to_local(l);
      if (wl.z() > 0 && l.dot(ng) > 0 && !scene.occluded(p, l, 0.0)) tap(wl, wo, light.irradiance * wl.z());
    }
    if (variate) *control.sum += controlled;
    return Rgb::Zero();
  }

  // Ground: Lambertian, sampled with the environment and cosine strategies only.
  const Rgb f_ground = desc.ground_albedo / kPi;
  const double pe = draw.ground_environment_probability, pc = 1.0 - pe;
  Rgb radiance = Rgb::Zero();
  const double share = draw.both ? 0.5 : 1.0;
  const auto ground_direction = [&](const Vec3& wi_world, const Vec3& wi, bool environment) {
    if (wi.z() <= 0) return;
    const double a = pe * env.pdf(wi_world), b = pc * cosine_pdf(wi);
    if (a + b > 0 && !scene.occluded(p, wi_world, 0.0))
      radiance += f_ground * env.eval(wi_world) * (share * wi.z() * mis_weight(draw.power, a, b, environment ? a : b));
  };
  if (draw.ground_environment || draw.both) {
    double pdf;
    const Vec3 wi_world = draw.both ? env.sample(draw.e0, draw.e1, &pdf) : env.sample(u0, u1, &pdf);
    ground_direction(wi_world, f.to_local(wi_world), true);
  }
  if (!draw.ground_environment) {
    const Vec3 wi = sample_cosine(u0, u1);
    ground_direction(f.to_world(wi), wi, false);
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
                    PixelBody&& body, RowShare share = {}) {
  std::atomic<std::uint64_t> rows_done{0};
  std::mutex progress_mutex;
  const auto rows = static_cast<std::uint64_t>(share.rows(settings.height));
  progress.update(label, 0, rows);
  parallel_for_each(0, static_cast<std::size_t>(rows), [&](std::size_t j) {
    const int y = share.row(static_cast<int>(j));
    for (int x = 0; x < settings.width; ++x) body(x, y);
    const std::uint64_t done = ++rows_done;
    std::lock_guard lock(progress_mutex);
    progress.update(label, done, rows);
  });
  progress.finish(label);
}

/// Camera samples per pixel (RenderSettings::grazing_samples): in proportion to 1 / cos(theta_o)
/// at the pixel centre's hit on the object, between 1 and the cap, the image's mean scaled back to
/// spp; empty when every pixel takes spp. Depends on the scene and the settings only.
std::vector<int> grazing_sample_counts(const Scene& scene, const RenderSettings& s) {
  if (s.pixel_samples) {  // the caller's shares
    std::vector<int> counts(s.pixel_samples->size());
    for (std::size_t p = 0; p < counts.size(); ++p)
      counts[p] = pixel_sample_count(s.spp, (*s.pixel_samples)[p]);
    return counts;
  }
  if (!(s.grazing_samples > 1.0)) return {};
  const std::size_t w = static_cast<std::size_t>(s.width), pixels = w * static_cast<std::size_t>(s.height);
  std::vector<double> boost(pixels, 1.0);
  parallel_for(0, static_cast<std::size_t>(s.height), [&](std::size_t y0, std::size_t y1) {
    Vec3 o, d;
    for (std::size_t y = y0; y < y1; ++y)
      for (std::size_t x = 0; x < w; ++x) {
        scene.camera_ray(static_cast<double>(x) + 0.5, static_cast<double>(y) + 0.5, s.width, s.height, &o, &d);
        const std::optional<Hit> hit = scene.intersect(o, d);
        if (!hit || !hit->object) continue;
        const double cos_o = std::max(1e-6, -hit->normal.dot(d));
        boost[y * w + x] = std::clamp(kGrazingCosine / cos_o, 1.0, s.grazing_samples);
      }
  });
  double mean = 0;
  for (const double b : boost) mean += b;
  mean /= static_cast<double>(pixels);
  std::vector<int> counts(pixels);
  for (std::size_t p = 0; p < pixels; ++p)
    counts[p] = std::max(1, static_cast<int>(std::lround(s.spp * boost[p] / mean)));
  return counts;
}

/// The samples of one render: which sampler, the camera samples of each pixel, and the stratified
/// sampler's split of a pixel's samples among the strategies (one plan per count).
struct Sampling {
  Sampling(const Scene& scene, const RenderSettings& s)
      : settings(s), stratified(s.sampler != Sampler::independent), both(s.sampler == Sampler::light_and_lobe),
        counts(grazing_sample_counts(scene, s)) {
    if (!stratified) return;
    const auto add = [&](int n) {
      if (plans.count(n)) return;
      StrategyPlan& plan = plans[n];
      plan = plan_strategies(both ? without_environment(s.mixture) : s.mixture, n);
      // Light and lobe: n environment samples besides the plan's n lobe samples.
      if (both) plan.density.environment = static_cast<double>(n);
    };
    add(s.spp);
    for (const int n : counts) add(n);
  }
  static SamplingMixture without_environment(SamplingMixture m) {
    m.environment = 0;
    return m;
  }
  /// Camera samples of pixel (x, y).
  int count(int x, int y) const {
    return counts.empty() ? settings.spp
                          : counts[static_cast<std::size_t>(y) * static_cast<std::size_t>(settings.width) +
                                   static_cast<std::size_t>(x)];
  }
  const StrategyPlan& plan(int n) const { return plans.at(n); }
  /// The density of a pixel's samples at the object (what trace_sample divides by).
  const SamplingMixture& density(int n) const { return stratified ? plan(n).density : settings.mixture; }
  std::uint64_t camera_samples() const {
    if (counts.empty())
      return static_cast<std::uint64_t>(settings.width) * static_cast<std::uint64_t>(settings.height) *
             static_cast<std::uint64_t>(settings.spp);
    std::uint64_t total = 0;
    for (const int n : counts) total += static_cast<std::uint64_t>(n);
    return total;
  }

  const RenderSettings& settings;
  bool stratified;
  bool both;  ///< Sampler::light_and_lobe
  std::vector<int> counts;
  std::map<int, StrategyPlan> plans;  ///< by sample count (stratified samplers)
};

/// Runs body(origin, dir, draw) for every camera sample of pixel (x, y). The numbers depend on
/// (seed, pixel, sample) only: every material sees exactly these samples, which is what makes an
/// image basis linear in the BRDF (render(), render_bank() and object_coverage() all go through
/// here). Independent: sample s takes the stream (seed, pixel, s), jitter then draw. Stratified
/// (render/pixel_sampler.h): the plan's counts per strategy, each strategy's samples stratified.
template <class Body>
void for_each_sample(const Scene& scene, const Sampling& sampling, int x, int y, Body&& body) {
  const RenderSettings& settings = sampling.settings;
  const std::uint64_t pixel =
      static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(settings.width) + static_cast<std::uint64_t>(x);
  Vec3 o, d;
  const int n = sampling.count(x, y);
  MATLAS_DCHECK(n > 0, "every pixel takes a sample");
  if (!sampling.stratified) {
    for (int s = 0; s < n; ++s) {
      SampleStream rng(settings.seed, pixel, static_cast<std::uint64_t>(s));
      const double jx = rng.next(), jy = rng.next();
      scene.camera_ray(x + jx, y + jy, settings.width, settings.height, &o, &d);
      Draw draw = independent_draw(settings.mixture, rng);
      draw.jx = jx, draw.jy = jy;
      body(o, d, draw);
    }
    return;
  }
  const PixelSampler sampler(settings.seed, pixel);
  const StrategyPlan& plan = sampling.plan(n);
  Draw draw;
  draw.both = sampling.both;
  draw.power = settings.power_heuristic;
  // Light and lobe: the ground's environment and cosine samples both count spp.
  draw.ground_environment_probability =
      sampling.both ? 0.5 : static_cast<double>(plan.counts[0]) / static_cast<double>(n);
  int s = 0;
  for (std::size_t k = 0; k < plan.counts.size(); ++k) {
    draw.environment = draw.ground_environment = k == 0 && !sampling.both;
    // The density's environment share (half the samples when both) comes first in its picks.
    draw.pick = sampling.both ? 0.5 + 0.5 * plan.pick[k] : plan.pick[k];
    for (int j = 0; j < plan.counts[k]; ++j, ++s) {
      double u[4];
      sampler.point(static_cast<int>(k), j, u);
      draw.u0 = u[2], draw.u1 = u[3];
      if (sampling.both) {  // jitter and environment direction: one stratified set over the pixel's spp
        sampler.point(static_cast<int>(plan.counts.size()), s, u);
        draw.e0 = u[2], draw.e1 = u[3];
      }
      scene.camera_ray(x + u[0], y + u[1], settings.width, settings.height, &o, &d);
      draw.jx = u[0], draw.jy = u[1];
      body(o, d, draw);
    }
  }
  MATLAS_DCHECK_EQ(s, n);  // the plan's counts sum to the pixel's samples
}

/// Returns the sum over the pixel's samples of the material-independent radiance; tap(wi, wo,
/// weight) is called for every BRDF evaluation on the object. Adds the number of taps to `taps`.
template <class Tap>
Rgb trace_pixel(const Scene& scene, const Sampling& sampling, int x, int y, Tap&& tap, std::uint64_t& taps,
                const Control& with = {}, Rgb* controlled = nullptr) {
  Rgb constant = Rgb::Zero();
  PixelControl control{with.variate, nullptr, with.grid, controlled};
  MATLAS_DCHECK(!with.variate || controlled, "a sum for the control variate's terms");
  if (with.variate && with.grid) {
    const ControlGrid::Cell& cell =
        with.grid->cells[static_cast<std::size_t>(y) * static_cast<std::size_t>(with.grid->width) + static_cast<std::size_t>(x)];
    if (cell.subdivisions == 0) control.variate = nullptr;  // no control variate in this pixel
    else control.cell = &cell;
  }
  const SamplingMixture& density = sampling.density(sampling.count(x, y));
  for_each_sample(scene, sampling, x, y, [&](const Vec3& o, const Vec3& d, const Draw& draw) {
    bool hit_object;
    constant += trace_sample(
        scene, density, draw, o, d, &hit_object,
        [&](const Vec3& wi, const Vec3& wo, const Rgb& w) {
          tap(wi, wo, w);
          ++taps;
        },
        control);
  });
  return constant;
}

void record_stats(RenderStats* stats, const Sampling& sampling, std::uint64_t taps,
                  std::chrono::steady_clock::time_point start) {
  if (!stats) return;
  stats->camera_samples = sampling.camera_samples();
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
  if (!(grazing_samples >= 1.0 && grazing_samples <= 64.0))
    throw Error("grazing_samples must be between 1 and 64, got " + std::to_string(grazing_samples));
  if (sampler == Sampler::light_and_lobe && !(mixture.total() - mixture.environment > 0))
    throw Error("the light-and-lobe sampler needs a lobe strategy (cosine, GGX or tabulated) besides the environment");
  check_pixel_samples(pixel_samples.get(), width, height);
}

Image render(const Scene& scene, const Material& material, const RenderSettings& settings,
             ProgressSink& progress, RenderStats* stats, const Control& control) {
  settings.validate();
  MATLAS_CHECK(!control.grid || (control.variate && control.grid->width == settings.width &&
                                 control.grid->height == settings.height),
               "a control grid of the render's size, with its control variate");
  if (control.plain) *control.plain = Image(settings.width, settings.height);
  const auto start = std::chrono::steady_clock::now();
  const Sampling sampling(scene, settings);
  Image image(settings.width, settings.height);
  std::atomic<std::uint64_t> taps{0};
  for_each_pixel(settings, progress, "render", [&](int x, int y) {
    std::uint64_t local_taps = 0;
    Rgb reflected = Rgb::Zero(), controlled = Rgb::Zero();
    const Rgb constant = trace_pixel(
        scene, sampling, x, y,
        [&](const Vec3& wi, const Vec3& wo, const Rgb& w) { reflected += w * material.eval(wi, wo); }, local_taps,
        control, &controlled);
    const double n = static_cast<double>(sampling.count(x, y));
    const Rgb plain = (constant + reflected) / n, sum = plain + controlled / n;
    float* out = image.pixel(x, y);
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(sum[c]);
    if (control.plain)
      for (int c = 0; c < 3; ++c) control.plain->pixel(x, y)[c] = static_cast<float>(plain[c]);
    taps += local_taps;
  });
  record_stats(stats, sampling, taps.load(), start);
  return image;
}

std::vector<Image> render_bank(const Scene& scene, const MaterialBank& bank, const RenderSettings& settings,
                               ProgressSink& progress, RenderStats* stats, RowShare share) {
  settings.validate();
  MATLAS_CHECK(share.parts >= 1 && share.part >= 0 && share.part < share.parts, "a share of the rows");
  const auto start = std::chrono::steady_clock::now();
  const Sampling sampling(scene, settings);
  const int k_count = bank.count();
  if (k_count <= 0) throw Error("material bank is empty");
  std::vector<Image> images(static_cast<std::size_t>(k_count), Image(settings.width, share.rows(settings.height)));
  MATLAS_CHECK(sampling.counts.empty() ||
                   sampling.counts.size() == static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height),
               "a sample count per pixel");
  std::atomic<std::uint64_t> taps{0};
  const std::size_t values = 3 * static_cast<std::size_t>(k_count);
  for_each_pixel(settings, progress, "render basis", [&](int x, int y) {
    thread_local std::vector<double> acc, f;
    acc.assign(values, 0.0);
    f.resize(values);
    std::uint64_t local_taps = 0;
    const Rgb constant = trace_pixel(scene, sampling, x, y,
                                     [&](const Vec3& wi, const Vec3& wo, const Rgb& w) {
                                       bank.eval_all(wi, wo, f.data());
                                       for (std::size_t k = 0; k < values; k += 3) {
                                         acc[k] += w[0] * f[k];
                                         acc[k + 1] += w[1] * f[k + 1];
                                         acc[k + 2] += w[2] * f[k + 2];
                                       }
                                     },
                                     local_taps);
    const double inv = 1.0 / static_cast<double>(sampling.count(x, y));
    const int row = (y - share.part) / share.parts;  // the share's row of image row y
    for (int k = 0; k < k_count; ++k) {
      float* out = images[static_cast<std::size_t>(k)].pixel(x, row);
      for (int c = 0; c < 3; ++c)
        out[c] = static_cast<float>((constant[c] + acc[3 * static_cast<std::size_t>(k) + static_cast<std::size_t>(c)]) * inv);
    }
    taps += local_taps;
  }, share);
  record_stats(stats, sampling, taps.load(), start);
  return images;
}

std::vector<float> object_coverage(const Scene& scene, const RenderSettings& settings) {
  settings.validate();
  const Sampling sampling(scene, settings);
  std::vector<float> coverage(static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height));
  parallel_for(0, static_cast<std::size_t>(settings.height), [&](std::size_t y0, std::size_t y1) {
    for (std::size_t y = y0; y < y1; ++y)
      for (int x = 0; x < settings.width; ++x) {
        int hits = 0;
        for_each_sample(scene, sampling, x, static_cast<int>(y), [&](const Vec3& o, const Vec3& d, const Draw&) {
          const auto hit = scene.intersect(o, d);
          hits += hit && hit->object;
        });
        coverage[y * static_cast<std::size_t>(settings.width) + static_cast<std::size_t>(x)] =
            static_cast<float>(hits) / static_cast<float>(sampling.count(x, static_cast<int>(y)));
      }
  });
  return coverage;
}

std::vector<int> sample_counts(const Scene& scene, const RenderSettings& settings) {
  settings.validate();
  std::vector<int> counts = grazing_sample_counts(scene, settings);
  if (counts.empty())
    counts.assign(static_cast<std::size_t>(settings.width) * static_cast<std::size_t>(settings.height), settings.spp);
  return counts;
}

}  // namespace matlas::render
