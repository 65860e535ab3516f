#include "pathtrace/progressive_trace.h"

#include "core/check.h"

namespace matlas::pathtrace {

void ProgressiveTraceSettings::validate() const {
  trace.validate();
  limits.validate(trace.spp, "progressive trace");
}

namespace {

const ProgressiveTraceSettings& validated(const ProgressiveTraceSettings& settings) {
  settings.validate();
  return settings;
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
            const TraceImages r = trace(*world_, bank_.get(), s, progress);
            return r.once.empty() ? r.p : r.full(0);
          },
          [first = settings_.trace.seed](int pass) { return pass_seed(first, pass); }, "progressive trace") {
  MATLAS_CHECK(world_ && bank_ && bank_->count() == 1);
}

std::uint64_t ProgressiveTrace::pass_seed(std::uint64_t seed, int pass) {
  return seed + 0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(pass) + 1);
}

}  // namespace matlas::pathtrace
