#pragma once
// What the renderer shades with: any BRDF f(wi, wo) in the local frame (normal +z), and banks of
// many materials evaluated together (for image bases and the path tracer's measured object). The
// estimators are linear in f: every sample's direction and weight are independent of the
// material. The renderer knows nothing of the manifold: model-backed materials and the model's
// bank are in atlas/model_material.h and atlas/model_bank.h.
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "brdf/brdf_table.h"
#include "brdf/tabulate.h"

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

/// A linear combination sum_k a_k T_k of tables on one grid (nearest-bin lookups; missing values
/// read as 0 in each table).
class TableCombination final : public Material {
public:
  /// tables and coefficients have the same length (>= 1) and the tables the same dims; the tables
  /// must outlive the material. Throws matlas::Error otherwise.
  TableCombination(std::vector<const BrdfTable*> tables, std::vector<double> coefficients);
  Rgb eval(const Vec3& wi, const Vec3& wo) const override;

private:
  std::vector<const BrdfTable*> tables_;
  std::vector<double> coefficients_;
};

/// Any callable BRDF (analytic models, tests).
class FunctionMaterial final : public Material {
public:
  explicit FunctionMaterial(BrdfFunction f) : f_(std::move(f)) {}
  Rgb eval(const Vec3& wi, const Vec3& wo) const override { return f_(wi, wo); }

private:
  BrdfFunction f_;
};

/// Many materials evaluated at once for the same directions: the image-basis pass
/// (render_bank), the path tracer's measured object (pathtrace::trace), the sampling fit.
class MaterialBank {
public:
  virtual ~MaterialBank() = default;
  virtual int count() const = 0;
  /// out[3 k + c] = f_k(wi, wo)[c] for k < count(). Called concurrently from several threads.
  virtual void eval_all(const Vec3& wi, const Vec3& wo, double* out) const = 0;
};

/// A bank of independent materials (each evaluated on its own), held elsewhere or owned.
class MaterialList final : public MaterialBank {
public:
  /// The materials must outlive the bank.
  explicit MaterialList(std::vector<const Material*> materials) : materials_(std::move(materials)) {}
  /// A bank that keeps its materials alive (a refinement that outlives its caller).
  static MaterialList owning(std::vector<std::shared_ptr<const Material>> materials);
  int count() const override { return static_cast<int>(materials_.size()); }
  void eval_all(const Vec3& wi, const Vec3& wo, double* out) const override;

private:
  std::vector<const Material*> materials_;
  std::vector<std::shared_ptr<const Material>> owned_;
};

}  // namespace matlas::render
