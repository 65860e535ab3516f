#pragma once
// What the renderer shades with: any BRDF f(wi, wo) in the local frame (normal +z), and banks of
// many materials evaluated together (for image bases). The renderer's estimator is linear in f:
// every sample's direction and weight are independent of the material.
#include <vector>

#include <Eigen/Core>

#include "brdf/brdf_table.h"
#include "brdf/tabulate.h"
#include "manifold/model.h"

namespace matlas::render {

/// A BRDF to render. eval is called concurrently from several threads.
class Material {
public:
  virtual ~Material() = default;
  /// f(wi, wo), physical units; wi and wo are unit vectors with z > 0.
  virtual Rgb eval(const Vec3& wi, const Vec3& wo) const = 0;
};

/// A tabulated BRDF by MERL's nearest-bin lookup (missing values read as 0).
class TableMaterial final : public Material {
public:
  explicit TableMaterial(const BrdfTable& table) : table_(table) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return table_.lookup(wi, wo); }

private:
  const BrdfTable& table_;
};

/// The model's material at weights w (nearest-bin lookup through Model::lookup: one dot product
/// of length n per channel, no table is built).
class ModelMaterial final : public Material {
public:
  ModelMaterial(const Model& model, Eigen::VectorXd weights) : model_(model), w_(std::move(weights)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return model_.lookup(wi, wo, w_); }

private:
  const Model& model_;
  Eigen::VectorXd w_;
};

/// Any callable BRDF (analytic models, tests).
class FunctionMaterial final : public Material {
public:
  explicit FunctionMaterial(BrdfFunction f) : f_(std::move(f)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return f_(wi, wo); }

private:
  BrdfFunction f_;
};

/// Many materials evaluated at once for the same directions (the image-basis pass).
class MaterialBank {
public:
  virtual ~MaterialBank() = default;
  virtual int count() const = 0;
  /// out[3 k + c] = f_k(wi, wo)[c] for k < count().
  virtual void eval_all(const Vec3& wi, const Vec3& wo, double* out) const = 0;
};

/// A bank of independent materials (each evaluated on its own).
class MaterialList final : public MaterialBank {
public:
  explicit MaterialList(std::vector<const Material*> materials) : materials_(std::move(materials)) {}
  int count() const override { return static_cast<int>(materials_.size()); }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override;

private:
  std::vector<const Material*> materials_;
};

/// The model's mean material (w = 0) followed by every database material i (w = e_i =
/// Model::material_weights(i), so dropped columns read 0 exactly as in ModelMaterial): count() is
/// n + 1. One bin index and one contiguous run of n stored values per channel serve all of them:
/// f_i = mean + centred_i, exactly Model::value(v, e_i).
class ModelBank final : public MaterialBank {
public:
  explicit ModelBank(const Model& model) : model_(model) {}
  int count() const override { return model_.count() + 1; }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override;

private:
  const Model& model_;
};

}  // namespace matlas::render
