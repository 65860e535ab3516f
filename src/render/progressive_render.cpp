#include "render/progressive_render.h"

#include <algorithm>
#include <array>
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

double median_noise(const Image& image, const std::vector<bool>& object) {
  MATLAS_CHECK_EQ(object.size(), image.pixel_count());
  double noise = 0, signal = 0;
  std::array<float, 9> window;
  for (int y = 1; y + 1 < image.height; ++y)
    for (int x = 1; x + 1 < image.width; ++x) {
      bool inside = true;
      for (int dy = -1; dy <= 1 && inside; ++dy)
        for (int dx = -1; dx <= 1 && inside; ++dx)
          inside = object[static_cast<std::size_t>(y + dy) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x + dx)];
      if (!inside) continue;
      for (int c = 0; c < 3; ++c) {
        std::size_t k = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) window[k++] = image.pixel(x + dx, y + dy)[c];
        std::nth_element(window.begin(), window.begin() + 4, window.end());
        const double v = image.pixel(x, y)[c], d = v - window[4];
        noise += d * d;
        signal += v * v;
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
  if (!settings_.control_variate || choice == ControlChoice::plain || refinement_.state().passes == 0)
    return render(*scene_, *material_, s, progress);
  // The second pass: both estimates of its samples, the less noisy kept.
  if (!control_variate_) {
    std::shared_ptr<const ControlVariate> made = settings_.control_variate();
    if (!made) return render(*scene_, *material_, s, progress);  // not ready: ask again next pass
    control_grid_ = control_grid(*scene_, s.width, s.height, *made, progress);
    control_variate_ = std::move(made);
  }
  Image plain;
  Image controlled = render(*scene_, *material_, s, progress, nullptr, {control_variate_.get(), &control_grid_, &plain});
  if (median_noise(controlled, object_) < median_noise(plain, object_)) {
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
