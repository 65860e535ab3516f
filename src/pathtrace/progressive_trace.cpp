#include "pathtrace/progressive_trace.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/check.h"
#include "core/error.h"
#include "render/progressive_render.h"

namespace matlas::pathtrace {

void ProgressiveTraceSettings::validate() const {
  trace.validate();
  if (!(target_error > 0) || !std::isfinite(target_error)) throw Error("progressive trace: target_error must be positive");
  if (min_converged_spp < 1 || max_pass_spp < 1) throw Error("progressive trace: pass sizes must be positive");
  if (max_spp < trace.spp) throw Error("progressive trace: max_spp is below the first pass's spp");
}

ProgressiveTrace::ProgressiveTrace(std::shared_ptr<const World> world, std::shared_ptr<const render::MaterialBank> bank,
                                   ProgressiveTraceSettings settings)
    : world_(std::move(world)), bank_(std::move(bank)), settings_(std::move(settings)) {
  MATLAS_CHECK(world_ && bank_ && bank_->count() == 1);
  settings_.validate();
  const std::size_t values = static_cast<std::size_t>(settings_.trace.width) * static_cast<std::size_t>(settings_.trace.height) * 3;
  for (auto& s : sum_) s.assign(values, 0.0);
}

std::uint64_t ProgressiveTrace::pass_seed(std::uint64_t seed, int pass) {
  return seed + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(pass) + 1);
}

ProgressiveTraceState ProgressiveTrace::state() const {
  std::lock_guard lock(state_mutex_);
  return state_;
}

Image ProgressiveTrace::image() const {
  std::lock_guard lock(state_mutex_);
  Image out(settings_.trace.width, settings_.trace.height);
  if (state_.spp == 0) return out;
  const double inv = 1.0 / state_.spp;
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = static_cast<float>((sum_[0][i] + sum_[1][i]) * inv);
  return out;
}

void ProgressiveTrace::add_pass(const Image& pass, int spp, double seconds) {
  std::lock_guard lock(state_mutex_);
  MATLAS_CHECK_EQ(pass.rgb.size(), sum_[0].size());
  const int h = half_spp_[0] <= half_spp_[1] ? 0 : 1;
  for (std::size_t i = 0; i < sum_[h].size(); ++i) sum_[h][i] += static_cast<double>(pass.rgb[i]) * spp;
  half_spp_[h] += spp;
  state_.spp += spp;
  state_.seconds += seconds;
  ++state_.passes;
  const double a = half_spp_[0], b = half_spp_[1];
  if (a > 0 && b > 0) {
    double squares = 0, signal = 0;
    for (std::size_t i = 0; i < sum_[0].size(); ++i) {
      const double d = sum_[0][i] / a - sum_[1][i] / b, mean = (sum_[0][i] + sum_[1][i]) / (a + b);
      squares += d * d;
      signal += mean * mean;
    }
    const double variance = squares * a * b / ((a + b) * (a + b));
    state_.relative_error = signal > 0 ? std::sqrt(variance / signal) : (variance > 0 ? std::numeric_limits<double>::infinity() : 0.0);
  }
  state_.converged = state_.spp >= settings_.max_spp ||
                     (state_.spp >= settings_.min_converged_spp && state_.relative_error <= settings_.target_error);
}

ProgressiveTraceState ProgressiveTrace::refine(double seconds, ProgressSink& progress) {
  std::lock_guard refining(refining_);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  for (bool first = true;; first = false) {
    const ProgressiveTraceState now = state();
    if (now.converged) return now;
    const int spp = render::next_pass_spp(settings_.trace.spp, settings_.max_pass_spp, settings_.max_spp, now.spp,
                                          now.seconds, seconds - elapsed(), first);
    if (spp == 0) return now;
    TraceSettings s = settings_.trace;
    s.spp = spp;
    s.seed = pass_seed(settings_.trace.seed, now.passes);
    const auto pass_start = std::chrono::steady_clock::now();
    const TraceImages r = trace(*world_, bank_.get(), s, progress);
    add_pass(r.once.empty() ? r.p : r.full(0), spp,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - pass_start).count());
    if (elapsed() >= seconds) return state();
  }
}

}  // namespace matlas::pathtrace
