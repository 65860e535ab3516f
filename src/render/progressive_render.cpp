#include "render/progressive_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/check.h"
#include "render/adaptive_sampling.h"

namespace matlas::render {

void ProgressiveSettings::validate() const {
  render.validate();
  limits.validate(render.spp, "progressive render");
  adaptive.validate();
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

Image ProgressiveRender::pass(RenderSettings s, ProgressSink& progress) {
  s.pixel_samples = pixel_samples_;  // the shares chosen by the trial (null: the grazing rule)
  const ControlChoice choice = control_;
  const bool controlled_now = choice == ControlChoice::controlled;
  const Control current = controlled_now ? Control{control_variate_.get(), &control_grid_, nullptr} : Control{};
  const bool variate_pending = settings_.control_variate && choice == ControlChoice::undecided;
  const bool shares_pending =
      settings_.adaptive.enabled && !pixel_samples_ && s.spp >= settings_.adaptive.min_trial_spp;
  if (!variate_pending && !shares_pending) return render(*scene_, *material_, s, progress, nullptr, current);
  const auto seconds_per_spp = [&](std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / s.spp;
  };
  const auto plain_pass = [&] {
    const auto start = std::chrono::steady_clock::now();
    Image image = render(*scene_, *material_, s, progress);
    plain_seconds_per_spp_ = seconds_per_spp(start);
    ++plain_passes_;
    return image;
  };
  if (plain_passes_ == 0) return plain_pass();  // the first image as fast as the plain estimator makes it
  bool trying = false;  // the control variate's trial
  if (variate_pending) {
    if (!control_variate_) {
      std::shared_ptr<const ControlVariate> made = settings_.control_variate();
      if (made) {
        control_grid_ = control_grid(*scene_, s.width, s.height, *made, progress);
        control_variate_ = std::move(made);
      }
    }
    trying = control_variate_ != nullptr;
    if (!trying && !shares_pending) return plain_pass();  // not ready: ask again next pass
  }
  // The trial: two independent halves (the pass's seed and another), each with the estimate in
  // use and, when the control variate is tried, the plain one of the same samples: their
  // differences measure each estimator's noise without the image's own structure, and the chosen
  // one's, pixel by pixel, the shares.
  const int spp_a = std::max(1, s.spp / 2), spp_b = std::max(1, s.spp - spp_a);
  RenderSettings half_a = s, half_b = s;
  half_a.spp = spp_a;
  half_b.spp = spp_b;
  half_b.seed = s.seed ^ 0xD1B54A32D192ED03ull;
  Image plain_a, plain_b, a, b;
  const auto start = std::chrono::steady_clock::now();
  if (control_variate_) {
    a = render(*scene_, *material_, half_a, progress, nullptr, {control_variate_.get(), &control_grid_, trying ? &plain_a : nullptr});
    b = render(*scene_, *material_, half_b, progress, nullptr, {control_variate_.get(), &control_grid_, trying ? &plain_b : nullptr});
  } else {
    plain_a = render(*scene_, *material_, half_a, progress);
    plain_b = render(*scene_, *material_, half_b, progress);
  }
  const double trial_seconds = seconds_per_spp(start);
  bool controlled = controlled_now;
  if (trying) {
    const double with = halves_noise(a, b, object_), without = halves_noise(plain_a, plain_b, object_);
    controlled = with * with * trial_seconds < without * without * plain_seconds_per_spp_;
  } else if (!controlled_now) {
    plain_seconds_per_spp_ = trial_seconds;
  }
  const Image& chosen_a = controlled ? a : plain_a;
  const Image& chosen_b = controlled ? b : plain_b;
  // What the trial chose takes effect once this pass's image is made (a cancelled pass leaves
  // everything as it was).
  const auto commit = [&] {
    if (!trying) return;
    control_ = controlled ? ControlChoice::controlled : ControlChoice::plain;
    if (!controlled) {
      control_variate_.reset();
      control_grid_ = {};
    }
  };
  if (shares_pending) {
    // The shares from the chosen estimator's halves; the refinement restarts without them (they
    // chose the shares) and a pass with the shares becomes its first.
    std::vector<int> samples = sample_counts(*scene_, half_a);
    const std::vector<int> more = sample_counts(*scene_, half_b);
    for (std::size_t p = 0; p < samples.size(); ++p) samples[p] += more[p];
    Image mean = chosen_a;
    for (std::size_t i = 0; i < mean.rgb.size(); ++i) mean.rgb[i] = 0.5f * (chosen_a.rgb[i] + chosen_b.rgb[i]);
    auto shares = std::make_shared<const std::vector<double>>(adaptive_pixel_samples(
        chosen_a, chosen_b, samples, settings_.adaptive, linear_and_shown_weights(mean, object_, settings_.shown)));
    s.pixel_samples = shares;
    s.seed ^= 0x94D049BB133111EBull;  // neither half's samples
    const Control control = controlled ? Control{control_variate_.get(), &control_grid_, nullptr} : Control{};
    Image image = render(*scene_, *material_, s, progress, nullptr, control);
    commit();
    pixel_samples_ = std::move(shares);
    refinement_.restart();  // (the shares are fixed from now on: every pass weighs its spp)
    return image;
  }
  // The pass's image: both halves by their samples (s.spp in all when s.spp >= 2).
  Image out(chosen_a.width, chosen_a.height);
  for (std::size_t i = 0; i < out.rgb.size(); ++i)
    out.rgb[i] = static_cast<float>((spp_a * static_cast<double>(chosen_a.rgb[i]) + spp_b * static_cast<double>(chosen_b.rgb[i])) /
                                    (spp_a + spp_b));
  commit();
  if (trying && controlled) refinement_.restart();  // this pass becomes the first: the plain ones are dropped
  return out;
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
