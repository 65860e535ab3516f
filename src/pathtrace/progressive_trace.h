#pragma once
// ProgressiveTrace: the GI image of one map point refined pass after pass while the user rests on
// it (the scene view's refinement, docs/GI.md), as render/progressive_render.h refines previews.
//
// Every pass is an independent trace() of the point's own material (a bank of one, the model's
// material at the point: the full image I = P + N z + I2 of m(x), no interpolated I2) with its own seed, none of them the basis's: each
// is an unbiased estimate of the same image, so passes are averaged weighted by their samples per
// pixel, and nothing of the basis (other sampling, interpolated I2) is mixed in. Passes go
// alternately into two halves A and B, which gives the error of the mean without a reference
// (with a and b samples, Var(mean) = Var(A - B) a b / (a + b)^2 per pixel); `relative_error` is
// the RMS of that error over the whole image relative to the image's RMS value.
#include <limits>
#include <memory>
#include <mutex>
#include <vector>

#include "core/progress.h"
#include "formats/image_io.h"
#include "pathtrace/tracer.h"
#include "pathtrace/world.h"

namespace matlas::pathtrace {

struct ProgressiveTraceSettings {
  /// Size, depth and density of every pass; `spp` is the first pass's samples, `seed` the seed
  /// the pass seeds derive from.
  TraceSettings trace;
  double target_error = 0.01;  ///< converged at this relative error (with min_converged_spp)
  int min_converged_spp = 64;
  int max_spp = 4096;
  int max_pass_spp = 64;       ///< a pass stops only at a row, so its length bounds how late a cancel lands
  /// Throws matlas::Error for a non-positive target or pass size, or max_spp below the first pass.
  void validate() const;
};

struct ProgressiveTraceState {
  int spp = 0;
  int passes = 0;
  double relative_error = std::numeric_limits<double>::infinity();  ///< estimated; inf before two passes
  double seconds = 0;  ///< trace time spent so far
  bool converged = false;
};

class ProgressiveTrace {
public:
  /// The world and the bank (one material) must outlive the refinement (shared pointers).
  ProgressiveTrace(std::shared_ptr<const World> world, std::shared_ptr<const render::MaterialBank> bank,
                   ProgressiveTraceSettings settings);

  /// Adds passes for about `seconds` (at least one, none once converged). One caller refines at a
  /// time. If `progress` throws, the pass under way is dropped and the state stays as it was.
  ProgressiveTraceState refine(double seconds, ProgressSink& progress = null_progress());
  ProgressiveTraceState state() const;
  /// The mean of every pass so far (black before the first).
  Image image() const;
  /// The seed of pass k (never the trace settings' own seed, which the basis uses).
  static std::uint64_t pass_seed(std::uint64_t seed, int pass);

private:
  void add_pass(const Image& pass, int spp, double seconds);

  std::shared_ptr<const World> world_;
  std::shared_ptr<const render::MaterialBank> bank_;
  ProgressiveTraceSettings settings_;
  std::mutex refining_;
  mutable std::mutex state_mutex_;
  std::vector<double> sum_[2];
  int half_spp_[2] = {0, 0};
  ProgressiveTraceState state_;
};

}  // namespace matlas::pathtrace
