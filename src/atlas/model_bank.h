#pragma once
// The model's tables as a render::MaterialBank: material 0 is the model's mean table (w = 0),
// material k >= 1 the input k - 1 (w = e_{k-1} = Model::material_weights(k - 1)). A bank may hold
// a contiguous range [first, last) of the n + 1, so that a GI basis can be traced a few materials
// at a time. One bin index and one contiguous run of n stored values per channel serve all of
// them: f_i = mean + centred_i, exactly Model::value(v, e_i). Dropped columns read 0 for every
// material, as Model::bin_rgb does. Image bases (model_basis.h), GI bases (gi_basis.h) and the
// sampling fit (sampling_fit.h) are made of it.
#include "manifold/model.h"
#include "render/material.h"

namespace matlas::atlas {

class ModelBank final : public render::MaterialBank {
public:
  /// All n + 1 materials (mean, inputs).
  explicit ModelBank(const Model& model) : ModelBank(model, 0, model.count() + 1) {}
  /// Materials [first, last) of the n + 1; matlas::Error for an empty or out-of-range range.
  ModelBank(const Model& model, int first, int last);
  int count() const override { return last_ - first_; }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override;

private:
  const Model& model_;
  int first_, last_;
};

}  // namespace matlas::atlas
