#pragma once
// The tables of a model as a TableBank: material 0 is the model's mean table (w = 0), material
// k >= 1 the input k - 1 (w = e_{k-1}); a bank may hold a contiguous range of them, so that a
// GI basis can be traced a few materials at a time. Dropped columns read 0 for every material,
// as Model::bin_rgb does.
#include "manifold/model.h"
#include "pathtrace/table_bank.h"

namespace matlas::pathtrace {

class ModelBank final : public TableBank {
public:
  /// Materials [first, last) of the n + 1 (mean, inputs); matlas::Error for an empty or
  /// out-of-range range.
  ModelBank(const Model& model, int first, int last);
  int count() const override { return last_ - first_; }
  const MerlDims& dims() const override { return model_.dims(); }
  void eval_bin(std::size_t bin, double* out) const override;

private:
  const Model& model_;
  int first_, last_;
};

/// One point of the model: m(w) = (1 - sum w) mean + sum_i w_i z_i through Model::bin_rgb (no
/// table is built; negative values of an extrapolation are kept, so the image stays linear in w).
class ModelPointBank final : public TableBank {
public:
  ModelPointBank(const Model& model, Eigen::VectorXd weights) : model_(model), w_(std::move(weights)) {}
  int count() const override { return 1; }
  const MerlDims& dims() const override { return model_.dims(); }
  void eval_bin(std::size_t bin, double* out) const override {
    const Rgb v = model_.bin_rgb(bin, w_);
    for (int c = 0; c < 3; ++c) out[c] = v[c];
  }

private:
  const Model& model_;
  Eigen::VectorXd w_;
};

}  // namespace matlas::pathtrace
