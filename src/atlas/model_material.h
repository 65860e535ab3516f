#pragma once
// The manifold's materials for the renderer (render/material.h): the model's material at any
// weights (the bank of the model's mean and database materials is atlas/model_bank.h).
#include <memory>

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
  const BrdfTable& table() const { return table_; }

private:
  BrdfTable table_;
};

/// The model's material at weights w (ModelMaterial: m(w) through Model::bin_rgb, negative values
/// of an extrapolation kept, so an image stays linear in w) as a bank of one that owns it: the
/// path tracer's measured object at one map point.
inline std::shared_ptr<const render::MaterialList> model_point_bank(const Model& model, Eigen::VectorXd weights) {
  return std::make_shared<const render::MaterialList>(
      render::MaterialList::owning({std::make_shared<const ModelMaterial>(model, std::move(weights))}));
}

}  // namespace matlas::atlas
