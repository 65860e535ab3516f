#include "atlas/model_material.h"

#include <vector>

namespace matlas::atlas {

void ModelBank::eval_all(const Vec3& wi, const Vec3& wo, double* out) const {
  const int n = model_.count();
  const std::size_t bins = model_.dims().bins();
  const std::size_t bin = bin_of(model_.dims(), wi, wo);
  thread_local std::vector<float> run;
  run.resize(static_cast<std::size_t>(n));
  for (int c = 0; c < 3; ++c) {
    const std::size_t v = static_cast<std::size_t>(c) * bins + bin;
    const int col = model_.column_of(v);
    if (col < 0) {  // dropped column: reads 0 for every material, as Model::bin_rgb does
      for (int k = 0; k <= n; ++k) out[3 * k + c] = 0.0;
      continue;
    }
    const double mean = model_.mean(static_cast<std::size_t>(col));
    model_.data(static_cast<std::size_t>(col), run.data());
    out[c] = mean;
    for (int i = 0; i < n; ++i) out[3 * (i + 1) + c] = static_cast<double>(run[static_cast<std::size_t>(i)]);
  }
}

}  // namespace matlas::atlas
