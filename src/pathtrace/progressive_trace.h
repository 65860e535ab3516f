#pragma once
// ProgressiveTrace: the GI image of one map point refined pass after pass while the user rests on
// it (the scene view's refinement, docs/GI.md): a render::Refinement (render/refinement.h, as
// previews refine) whose passes are independent trace()s of the point's own material (a bank of
// one, the model's material at the point: the full image I = P + N z + I2 of m(x), no interpolated
// I2), each with its own seed, none of them the basis's, and whose error is measured over the
// whole image. Nothing of the basis (other sampling, interpolated I2) is mixed in.
#include <cstdint>
#include <memory>

#include "core/progress.h"
#include "formats/image_io.h"
#include "pathtrace/tracer.h"
#include "render/refinement.h"
#include "pathtrace/world.h"

namespace matlas::pathtrace {

struct ProgressiveTraceSettings {
  /// Size, depth and density of every pass; `spp` is the first pass's samples, `seed` the seed
  /// the pass seeds derive from.
  TraceSettings trace;
  /// A GI pass stops only at a row, so its length (max_pass_spp) bounds how late a cancel lands.
  render::RefinementLimits limits{.target_error = 0.01, .min_converged_spp = 64, .max_spp = 4096, .max_pass_spp = 64};
  /// Throws matlas::Error for invalid limits (render::RefinementLimits::validate) and whatever
  /// TraceSettings::validate throws.
  void validate() const;
};

class ProgressiveTrace {
public:
  /// The world and the bank (one material) must outlive the refinement (shared pointers).
  ProgressiveTrace(std::shared_ptr<const World> world, std::shared_ptr<const render::MaterialBank> bank,
                   ProgressiveTraceSettings settings);

  /// Adds passes for about `seconds` (render::Refinement::refine).
  render::RefinementState refine(double seconds, ProgressSink& progress = null_progress()) {
    return refinement_.refine(seconds, progress);
  }
  render::RefinementState state() const { return refinement_.state(); }
  /// The mean of every pass so far (black before the first).
  Image image() const { return refinement_.image(); }
  /// The seed of pass k (never the trace settings' own seed, which the basis uses).
  static std::uint64_t pass_seed(std::uint64_t seed, int pass);

private:
  std::shared_ptr<const World> world_;
  std::shared_ptr<const render::MaterialBank> bank_;
  ProgressiveTraceSettings settings_;
  render::Refinement refinement_;
};

}  // namespace matlas::pathtrace
