#include "pathtrace/model_bank.h"

#include <vector>

#include "core/error.h"

namespace matlas::pathtrace {

ModelBank::ModelBank(const Model& model, int first, int last) : model_(model), first_(first), last_(last) {
  if (first < 0 || last > model.count() + 1 || first >= last)
    throw Error("model bank: materials [" + std::to_string(first) + ", " + std::to_string(last) +
                ") out of the model's 0.." + std::to_string(model.count()));
}

void ModelBank::eval_bin(std::size_t bin, double* out) const {
  const std::size_t bins = model_.dims().bins();
  thread_local std::vector<float> run;
  run.resize(static_cast<std::size_t>(model_.count()));
  for (int c = 0; c < 3; ++c) {
    const int col = model_.column_of(static_cast<std::size_t>(c) * bins + bin);
    if (col >= 0 && last_ > 1) model_.data(static_cast<std::size_t>(col), run.data());
    for (int k = first_; k < last_; ++k) {
      double v = 0.0;
      if (col >= 0)
        v = k == 0 ? static_cast<double>(model_.mean(static_cast<std::size_t>(col)))
                   : static_cast<double>(run[static_cast<std::size_t>(k - 1)]);
      out[3 * static_cast<std::size_t>(k - first_) + static_cast<std::size_t>(c)] = v;
    }
  }
}

}  // namespace matlas::pathtrace
