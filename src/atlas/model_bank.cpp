#include "atlas/model_bank.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/error.h"

namespace matlas::atlas {

ModelBank::ModelBank(const Model& model, int first, int last) : model_(model), first_(first), last_(last) {
  if (first < 0 || last > model.count() + 1 || first >= last)
    throw Error("model bank: materials [" + std::to_string(first) + ", " + std::to_string(last) +
                ") out of the model's 0.." + std::to_string(model.count()));
}

void ModelBank::eval_all(const Vec3& wi, const Vec3& wo, double* out) const {
  const std::size_t bins = model_.dims().bins();
  const std::size_t bin = bin_of(model_.dims(), wi, wo);
  MATLAS_DCHECK_LT(bin, bins);
  thread_local std::vector<float> run;
  run.resize(static_cast<std::size_t>(model_.count()));
  for (int c = 0; c < 3; ++c) {
    const int col = model_.column_of(static_cast<std::size_t>(c) * bins + bin);
    double* o = out + c;
    if (col < 0) {  // dropped column: reads 0 for every material, as Model::bin_rgb does
      for (int k = first_; k < last_; ++k) o[3 * (k - first_)] = 0.0;
      continue;
    }
    if (first_ == 0) *o = static_cast<double>(model_.mean(static_cast<std::size_t>(col)));
    if (last_ > 1) {
      model_.data(static_cast<std::size_t>(col), run.data());
      for (int k = std::max(first_, 1); k < last_; ++k)
        o[3 * (k - first_)] = static_cast<double>(run[static_cast<std::size_t>(k - 1)]);
    }
  }
}

}  // namespace matlas::atlas
