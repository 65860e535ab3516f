#include "render/progressive_render.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>

#include "core/check.h"
#include "core/error.h"

namespace matlas::render {

void ProgressiveSettings::validate() const {
  render.validate();
  if (!(target_error > 0) || !std::isfinite(target_error))
    throw Error("progressive render: target_error must be positive, got " + std::to_string(target_error));
  if (min_converged_spp < 1) throw Error("progressive render: min_converged_spp must be at least 1");
  if (max_pass_spp < 1) throw Error("progressive render: max_pass_spp must be at least 1");
  if (max_spp < render.spp)
    throw Error("progressive render: max_spp (" + std::to_string(max_spp) + ") is below the first pass's spp (" +
                std::to_string(render.spp) + ")");
}

ProgressiveRender::ProgressiveRender(std::shared_ptr<const Scene> scene, std::shared_ptr<const Material> material,
                                     ProgressiveSettings settings)
    : scene_(std::move(scene)), material_(std::move(material)), settings_(std::move(settings)) {
  MATLAS_CHECK(scene_ && material_);
  settings_.validate();
  const std::vector<float> coverage = object_coverage(*scene_, settings_.render);
  object_.resize(coverage.size());
  region_.resize(coverage.size());
  bool any = false;
  for (std::size_t i = 0; i < coverage.size(); ++i) {
    any |= (object_[i] = coverage[i] >= 1.0f);
    region_[i] = coverage[i] >= 1.0f ? 1 : coverage[i] <= 0.0f ? 2 : 0;
  }
  if (!any) std::fill(object_.begin(), object_.end(), true);  // no pixel sees only the object: measure all
  for (auto& s : sum_) s.assign(coverage.size() * 3, 0.0);
}

ProgressiveState ProgressiveRender::state() const {
  std::lock_guard lock(state_mutex_);
  return state_;
}

Image ProgressiveRender::image() const {
  std::lock_guard lock(state_mutex_);
  return mean_locked();
}

Image ProgressiveRender::mean_locked() const {
  Image out(settings_.render.width, settings_.render.height);
  if (state_.spp == 0) return out;
  const double inv = 1.0 / state_.spp;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = static_cast<float>((sum_[0][i] + sum_[1][i]) * inv);
  return out;
}

DenoiseResult ProgressiveRender::denoised(const DenoiseSettings& settings) const {
  Image halves[2];
  double samples[2];
  {
    std::lock_guard lock(state_mutex_);
    if (half_spp_[0] == 0 || half_spp_[1] == 0) {
      DenoiseResult plain;
      plain.image = mean_locked();
      plain.relative_error = state_.relative_error;
      return plain;
    }
    for (int h = 0; h < 2; ++h) {
      halves[h] = Image(settings_.render.width, settings_.render.height);
      samples[h] = half_spp_[h];
      for (std::size_t i = 0; i < halves[h].rgb.size(); ++i) halves[h].rgb[i] = static_cast<float>(sum_[h][i] / samples[h]);
    }
  }
  return denoise_halves(halves[0], halves[1], samples[0], samples[1], region_, object_, settings);
}

void ProgressiveRender::add_pass(const Image& pass, int spp, double seconds) {
  std::lock_guard lock(state_mutex_);
  MATLAS_CHECK_EQ(pass.rgb.size(), sum_[0].size());
  const int h = half_spp_[0] <= half_spp_[1] ? 0 : 1;
  auto& sum = sum_[h];
  for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += static_cast<double>(pass.rgb[i]) * spp;
  half_spp_[h] += spp;
  state_.spp += spp;
  state_.seconds += seconds;
  ++state_.passes;
  update_error();
}

void ProgressiveRender::update_error() {
  const double a = half_spp_[0], b = half_spp_[1];
  if (a == 0 || b == 0) return;
  double squares = 0, signal = 0;
  for (std::size_t p = 0; p < object_.size(); ++p) {
    if (!object_[p]) continue;
    for (std::size_t c = 0; c < 3; ++c) {
      const std::size_t i = p * 3 + c;
      const double d = sum_[0][i] / a - sum_[1][i] / b;
      const double mean = (sum_[0][i] + sum_[1][i]) / (a + b);
      squares += d * d;
      signal += mean * mean;
    }
  }
  const double variance = squares * a * b / ((a + b) * (a + b));
  state_.relative_error = signal > 0 ? std::sqrt(variance / signal) : (variance > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  state_.converged = state_.spp >= settings_.max_spp ||
                     (state_.spp >= settings_.min_converged_spp && state_.relative_error <= settings_.target_error);
}

int next_pass_spp(int first_spp, int max_pass_spp, int max_spp, int spp_in, double seconds_in, double seconds_left,
                  bool first) {
  if (spp_in == 0) return first_spp;
  const double fits = seconds_left / std::max(seconds_in / spp_in, 1e-9);
  const int limit = std::max(1, std::min({max_pass_spp, std::max(first_spp, spp_in), max_spp - spp_in}));
  const int least = std::min(first_spp, limit);  // passes are never smaller than the first
  if (!first && fits < least) return 0;         // no time for another pass
  const int spp = static_cast<int>(std::bit_floor(static_cast<unsigned>(std::clamp(fits, 1.0, static_cast<double>(limit)))));
  return std::clamp(spp, least, limit);
}

ProgressiveState ProgressiveRender::refine(double seconds, ProgressSink& progress) {
  std::lock_guard refining(refining_);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  for (bool first = true;; first = false) {
    ProgressiveState now = state();
    if (now.converged) return now;
    const int spp = next_pass_spp(settings_.render.spp, settings_.max_pass_spp, settings_.max_spp, now.spp, now.seconds,
                                  seconds - elapsed(), first);
    if (spp == 0) return now;
    RenderSettings s = settings_.render;
    s.spp = spp;
    s.seed = settings_.render.seed + 0x9E3779B97F4A7C15ull * static_cast<std::uint64_t>(now.passes);
    const auto pass_start = std::chrono::steady_clock::now();
    const Image pass = render(*scene_, *material_, s, progress);
    const double pass_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count();
    add_pass(pass, spp, pass_seconds);
    if (elapsed() >= seconds) return state();
  }
}

}  // namespace matlas::render
