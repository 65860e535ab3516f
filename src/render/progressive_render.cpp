#include "render/progressive_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/check.h"

namespace matlas::render {

void ProgressiveSettings::validate() const {
  render.validate();
  limits.validate(render.spp, "progressive render");
}

std::vector<float> ProgressiveRender::checked_coverage(const Scene* scene, const ProgressiveSettings& settings) {
  MATLAS_CHECK(scene != nullptr);
  settings.validate();
  return object_coverage(*scene, settings.render);
}

namespace {

/// Per pixel, whether it sees only the object (all pixels when none does: then the whole image is
/// measured).
std::vector<bool> object_only(const std::vector<float>& coverage) {
  std::vector<bool> object(coverage.size());
  bool any = false;
  for (std::size_t i = 0; i < coverage.size(); ++i) any |= (object[i] = coverage[i] >= 1.0f);
  if (!any) std::fill(object.begin(), object.end(), true);
  return object;
}

}  // namespace

double halves_noise(const Image& a, const Image& b, const std::vector<bool>& object) {
  MATLAS_CHECK(a.rgb.size() == b.rgb.size() && object.size() == a.pixel_count(), "two halves of one image");
  double noise = 0, signal = 0;
  for (std::size_t p = 0; p < object.size(); ++p) {
    if (!object[p]) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = a.rgb[3 * p + c], y = b.rgb[3 * p + c];
      noise += (x - y) * (x - y);
      signal += 0.25 * (x + y) * (x + y);
    }
  }
  return signal > 0 ? std::sqrt(noise / signal) : 0.0;
}

ProgressiveRender::ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                                     ProgressiveSettings settings)
    : ProgressiveRender(scene, std::move(material), settings, checked_coverage(scene.get(), settings)) {}

ProgressiveRender::ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                                     const ProgressiveSettings& settings, const std::vector<float>& coverage)
    : scene_(std::move(scene)), material_(std::move(material)), settings_(settings), object_(object_only(coverage)),
      refinement_(
          settings_.render.width, settings_.render.height, object_, settings_.render.spp, settings_.limits,
          [this](int spp, std::uint64_t seed, ProgressSink& progress) {
            RenderSettings s = settings_.render;
            s.spp = spp;
            s.seed = seed;
            return pass(s, progress);
          },
          [first = settings_.render.seed](int pass) {
            return first + 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(pass);
          },
          "progressive render") {
  MATLAS_CHECK(material_ != nullptr);
  region_.resize(coverage.size());
  for (std::size_t i = 0; i < coverage.size(); ++i) region_[i] = coverage[i] >= 1.0f ? 1 : coverage[i] <= 0.0f ? 2 : 0;
}

Image ProgressiveRender::pass(const RenderSettings& s, ProgressSink& progress) {
  const ControlChoice choice = control_;
  if (choice == ControlChoice::controlled)
    return render(*scene_, *material_, s, progress, nullptr, {control_variate_.get(), &control_grid_, nullptr});
  const auto seconds_per_spp = [&](std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / s.spp;
  };
  const auto plain_pass = [&] {
    const auto start = std::chrono::steady_clock::now();
    Image image = render(*scene_, *material_, s, progress);
    plain_seconds_per_spp_ = seconds_per_spp(start);
    return image;
  };
  if (!settings_.control_variate || choice == ControlChoice::plain) return render(*scene_, *material_, s, progress);
  if (refinement_.state().passes == 0) return plain_pass();
  // The second pass: both estimates of its samples; the control variate is kept when its noise
  // per unit of time is lower (its passes cost more than plain ones).
  if (!control_variate_) {
    std::shared_ptr<const ControlVariate> made = settings_.control_variate();
    if (!made) return plain_pass();  // not ready: ask again next pass
    control_grid_ = control_grid(*scene_, s.width, s.height, *made, progress);
    control_variate_ = std::move(made);
  }
  // Two independent halves (the pass's seed and another), each with both estimates: their
  // differences measure each estimator's noise without the image's own structure.
  const int spp_a = std::max(1, s.spp / 2), spp_b = std::max(1, s.spp - spp_a);
  RenderSettings half = s;
  half.spp = spp_a;
  Image plain_a, plain_b;
  const auto start = std::chrono::steady_clock::now();
  const Image a = render(*scene_, *material_, half, progress, nullptr, {control_variate_.get(), &control_grid_, &plain_a});
  half.spp = spp_b;
  half.seed = s.seed ^ 0xD1B54A32D192ED03ull;
  const Image b = render(*scene_, *material_, half, progress, nullptr, {control_variate_.get(), &control_grid_, &plain_b});
  const double controlled_seconds = seconds_per_spp(start);
  const double with = halves_noise(a, b, object_), without = halves_noise(plain_a, plain_b, object_);
  // The pass's image: both halves by their samples (s.spp in all when s.spp >= 2).
  const auto join = [&](const Image& x, const Image& y) {
    Image out(x.width, x.height);
    const double wx = spp_a, wy = spp_b;
    for (std::size_t i = 0; i < out.rgb.size(); ++i)
      out.rgb[i] = static_cast<float>((wx * x.rgb[i] + wy * y.rgb[i]) / (wx + wy));
    return out;
  };
  const Image controlled = join(a, b), plain = join(plain_a, plain_b);
  if (with * with * controlled_seconds < without * without * plain_seconds_per_spp_) {
    control_ = ControlChoice::controlled;
    refinement_.restart();  // this pass becomes the first: the plain one is dropped
    return controlled;
  }
  control_ = ControlChoice::plain;
  control_variate_.reset();
  control_grid_ = {};
  return plain;
}

DenoiseResult ProgressiveRender::denoised(const DenoiseSettings& settings) const {
  const RefinementHalves h = refinement_.halves();
  if (h.samples_a == 0 || h.samples_b == 0) {
    DenoiseResult plain;
    plain.image = refinement_.image();
    plain.relative_error = refinement_.state().relative_error;
    return plain;
  }
  return denoise_halves(h.a, h.b, h.samples_a, h.samples_b, region_, object_, settings);
}

}  // namespace matlas::render
