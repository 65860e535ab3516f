#include "render/progressive_render.h"

#include <algorithm>

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
            return render(*scene_, *material_, s, progress);
          },
          [first = settings_.render.seed](int pass) {
            return first + 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(pass);
          },
          "progressive render") {
  MATLAS_CHECK(material_ != nullptr);
  region_.resize(coverage.size());
  for (std::size_t i = 0; i < coverage.size(); ++i) region_[i] = coverage[i] >= 1.0f ? 1 : coverage[i] <= 0.0f ? 2 : 0;
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
