#include "pathtrace/progressive_trace.h"

#include <algorithm>

#include "core/check.h"
#include "core/parallel.h"
#include "render/auto_exposure.h"
#include "render/firefly_filter.h"

namespace matlas::pathtrace {

void ProgressiveTraceSettings::validate() const {
  trace.validate();
  limits.validate(trace.spp, "progressive trace");
  adaptive.validate();
}

namespace {

const ProgressiveTraceSettings& validated(const ProgressiveTraceSettings& settings) {
  settings.validate();
  return settings;
}

/// ProgressiveTrace::regions(): the first hits of 2 x 2 rays per pixel.
std::vector<std::uint8_t> first_hit_regions(const World& world, int width, int height) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  parallel_for_each(0, static_cast<std::size_t>(height), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    for (int x = 0; x < width; ++x) {
      int label = -1;
      for (int k = 0; k < 4 && label != 0; ++k) {
        Vec3 o, d;
        world.camera_ray(x + 0.25 + 0.5 * (k % 2), y + 0.25 + 0.5 * (k / 2), width, height, &o, &d);
        const auto hit = world.intersect(o, d);
        const int seen = hit ? std::min(hit->object + 1, 255) : 255;
        label = label < 0 || label == seen ? seen : 0;
      }
      out[row * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] = static_cast<std::uint8_t>(label);
    }
  });
  return out;
}

}  // namespace

ProgressiveTrace::ProgressiveTrace(std::shared_ptr<const World> world, std::shared_ptr<const render::MaterialBank> bank,
                                   ProgressiveTraceSettings settings)
    : world_(std::move(world)), bank_(std::move(bank)), settings_(validated(settings)),
      refinement_(
          settings_.trace.width, settings_.trace.height, {}, settings_.trace.spp, settings_.limits,
          [this](int spp, std::uint64_t seed, ProgressSink& progress) {
            TraceSettings s = settings_.trace;
            s.spp = spp;
            s.seed = seed;
            return pass(s, progress);
          },
          [first = settings_.trace.seed](int pass) { return pass_seed(first, pass); }, "progressive trace") {
  MATLAS_CHECK(world_ && bank_ && bank_->count() == 1);
  region_ = first_hit_regions(*world_, settings_.trace.width, settings_.trace.height);
}

render::DenoiseResult ProgressiveTrace::denoised(const render::DenoiseSettings& settings) const {
  const render::RefinementHalves h = refinement_.halves();
  if (h.samples_a == 0 || h.samples_b == 0) {
    render::DenoiseResult plain;
    plain.image = refinement_.image();
    plain.relative_error = refinement_.state().relative_error;
    return plain;
  }
  // Each half's lone fireflies first (render/firefly_filter.h): the filter would spread them over
  // the pixels whose patches resemble theirs, small bright squares on the object at 100+ spp.
  Image a = h.a, b = h.b;
  render::remove_fireflies(a);
  render::remove_fireflies(b);
  return render::denoise_halves(a, b, h.samples_a, h.samples_b, region_, {}, settings);
}

Image ProgressiveTrace::pass(TraceSettings s, ProgressSink& progress) {
  const auto traced = [&](const TraceSettings& t) {
    const TraceImages r = trace(*world_, bank_.get(), t, progress);
    return r.once.empty() ? r.p : r.full(0);
  };
  s.pixel_samples = pixel_samples_;
  if (!settings_.adaptive.enabled || pixel_samples_ || passes_ == 0 || s.spp < settings_.adaptive.min_trial_spp) {
    Image image = traced(s);
    ++passes_;
    return image;
  }
  // The trial: two independent halves (the pass's seed and another) whose difference, pixel by
  // pixel, gives the shares; the refinement restarts without them and a pass with the shares
  // (neither half's seed) becomes its first.
  TraceSettings half_a = s, half_b = s;
  half_a.spp = std::max(1, s.spp / 2);
  half_b.spp = std::max(1, s.spp - half_a.spp);
  half_b.seed = s.seed ^ 0xD1B54A32D192ED03ull;
  const Image a = traced(half_a), b = traced(half_b);
  // The error weighed as a linear figure and as shown (ACES at the automatic exposure, the scene
  // view's default).
  Image mean = a;
  for (std::size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] = 0.5f * (a.rgb[i] + b.rgb[i]);
  const ToneMap shown{ToneMap::Curve::aces, render::auto_exposure(mean)};
  auto shares = std::make_shared<const std::vector<double>>(render::adaptive_pixel_samples(
      a, b, std::vector<int>(a.pixel_count(), half_a.spp + half_b.spp), settings_.adaptive,
      render::linear_and_shown_weights(mean, std::vector<bool>(mean.pixel_count(), true), shown)));
  s.pixel_samples = shares;
  s.seed ^= 0x94D049BB133111EBull;
  Image image = traced(s);
  pixel_samples_ = std::move(shares);
  refinement_.restart();  // (the shares are fixed from now on: every pass weighs its spp)
  return image;
}

std::uint64_t ProgressiveTrace::pass_seed(std::uint64_t seed, int pass) {
  return seed + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(pass) + 1);
}

}  // namespace matlas::pathtrace
