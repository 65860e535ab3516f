#pragma once
// The manifold's materials for the renderer (render/material.h): the model's material at any
// weights, and the bank of the model's mean and database materials that image bases are made of.
#include <Eigen/Core>

#include "manifold/model.h"
#include "render/material.h"

namespace matlas::atlas {

/// The model's material at weights w (nearest-bin lookup through Model::lookup: one dot product
/// of length n per channel, no table is built).
class ModelMaterial final : public render::Material {
public:
  ModelMaterial(const Model& model, Eigen::VectorXd weights) : model_(model), w_(std::move(weights)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return model_.lookup(wi, wo, w_); }

private:
  const Model& model_;
  Eigen::VectorXd w_;
};

/// The model's material at weights w as a table, built once (Model::table: one pass over the
/// stored data, in parallel), for renders with many lookups: a lookup then reads one value per
/// channel instead of a dot product of length n. The same values as ModelMaterial (to rounding).
class ModelTableMaterial final : public render::Material {
public:
  ModelTableMaterial(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& weights) : table_(model.table(weights)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return table_.lookup(wi, wo); }

private:
  BrdfTable table_;
};

/// The model's mean material (w = 0) followed by every database material i (w = e_i =
/// Model::material_weights(i), so dropped columns read 0 exactly as in ModelMaterial): count() is
/// n + 1. One bin index and one contiguous run of n stored values per channel serve all of them:
/// f_i = mean + centred_i, exactly Model::value(v, e_i).
class ModelBank final : public render::MaterialBank {
public:
  explicit ModelBank(const Model& model) : model_(model) {}
  int count() const override { return model_.count() + 1; }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override;

private:
  const Model& model_;
};

}  // namespace matlas::atlas
