#include "render/refinement.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <string>

#include "core/check.h"
#include "core/error.h"

namespace matlas::render {

void RefinementLimits::validate(int first_spp, const char* who) const {
  const std::string name(who);
  if (!(target_error > 0) || !std::isfinite(target_error))
    throw Error(name + ": target_error must be positive, got " + std::to_string(target_error));
  if (min_converged_spp < 1) throw Error(name + ": min_converged_spp must be at least 1");
  if (max_pass_spp < 1) throw Error(name + ": max_pass_spp must be at least 1");
  if (max_spp < first_spp)
    throw Error(name + ": max_spp (" + std::to_string(max_spp) + ") is below the first pass's spp (" +
                std::to_string(first_spp) + ")");
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

Refinement::Refinement(int width, int height, std::vector<bool> measured, int first_spp, RefinementLimits limits,
                       Pass pass, PassSeed seed, const char* who)
    : width_(width), height_(height), measured_(std::move(measured)), first_spp_(first_spp), limits_(limits),
      pass_(std::move(pass)), seed_(std::move(seed)) {
  MATLAS_CHECK(width_ > 0 && height_ > 0 && pass_ && seed_);
  limits_.validate(first_spp_, who);
  const std::size_t pixels = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (measured_.empty()) measured_.assign(pixels, true);
  MATLAS_CHECK_EQ(measured_.size(), pixels);
  for (auto& s : sum_) s.assign(pixels * 3, 0.0);
}

RefinementState Refinement::state() const {
  std::lock_guard lock(state_mutex_);
  return state_;
}

Image Refinement::image() const {
  std::lock_guard lock(state_mutex_);
  return mean_locked();
}

Image Refinement::mean_locked() const {
  Image out(width_, height_);
  if (state_.spp == 0) return out;
  const double inv = 1.0 / state_.spp;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = static_cast<float>((sum_[0][i] + sum_[1][i]) * inv);
  return out;
}

RefinementHalves Refinement::halves() const {
  RefinementHalves out;
  std::lock_guard lock(state_mutex_);
  if (half_spp_[0] == 0 || half_spp_[1] == 0) return out;
  Image* images[2] = {&out.a, &out.b};
  for (int h = 0; h < 2; ++h) {
    *images[h] = Image(width_, height_);
    for (std::size_t i = 0; i < images[h]->rgb.size(); ++i)
      images[h]->rgb[i] = static_cast<float>(sum_[h][i] / half_spp_[h]);
  }
  out.samples_a = half_spp_[0];
  out.samples_b = half_spp_[1];
  return out;
}

void Refinement::add_pass(const Image& pass, int spp, double seconds) {
  std::lock_guard lock(state_mutex_);
  MATLAS_CHECK_EQ(pass.rgb.size(), sum_[0].size());
  const int h = half_spp_[0] <= half_spp_[1] ? 0 : 1;
  auto& sum = sum_[h];
  for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += static_cast<double>(pass.rgb[i]) * spp;
  half_spp_[h] += spp;
  state_.spp += spp;
  state_.seconds += seconds;
  ++state_.passes;
  const double a = half_spp_[0], b = half_spp_[1];
  if (a > 0 && b > 0) {
    double squares = 0, signal = 0;
    for (std::size_t p = 0; p < measured_.size(); ++p) {
      if (!measured_[p]) continue;
      for (std::size_t c = 0; c < 3; ++c) {
        const std::size_t i = p * 3 + c;
        const double d = sum_[0][i] / a - sum_[1][i] / b;
        const double mean = (sum_[0][i] + sum_[1][i]) / (a + b);
        squares += d * d;
        signal += mean * mean;
      }
    }
    const double variance = squares * a * b / ((a + b) * (a + b));
    state_.relative_error =
        signal > 0 ? std::sqrt(variance / signal) : (variance > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  }
  state_.converged = state_.spp >= limits_.max_spp ||
                     (state_.spp >= limits_.min_converged_spp && state_.relative_error <= limits_.target_error);
}

void Refinement::restart() {
  std::lock_guard lock(state_mutex_);
  for (auto& sum : sum_) std::fill(sum.begin(), sum.end(), 0.0);
  half_spp_[0] = half_spp_[1] = 0;
  state_ = RefinementState{};
}

RefinementState Refinement::refine(double seconds, ProgressSink& progress) {
  std::lock_guard refining(refining_);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  for (bool first = true;; first = false) {
    const RefinementState now = state();
    if (now.converged) return now;
    const int spp =
        next_pass_spp(first_spp_, limits_.max_pass_spp, limits_.max_spp, now.spp, now.seconds, seconds - elapsed(), first);
    if (spp == 0) return now;
    const auto pass_start = std::chrono::steady_clock::now();
    const Image pass = pass_(spp, seed_(seeds_used_), progress);
    ++seeds_used_;  // after the pass: a cancelled one leaves everything as it was
    add_pass(pass, spp, std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count());
    if (elapsed() >= seconds) return state();
  }
}

}  // namespace matlas::render
