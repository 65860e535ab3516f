#include "render/material.h"

#include "core/error.h"

namespace matlas::render {

TableCombination::TableCombination(std::vector<const BrdfTable*> tables, std::vector<double> coefficients)
    : tables_(std::move(tables)), coefficients_(std::move(coefficients)) {
  if (tables_.empty() || tables_.size() != coefficients_.size())
    throw Error("table combination: " + std::to_string(tables_.size()) + " tables and " +
                std::to_string(coefficients_.size()) + " coefficients (expected the same count, at least 1)");
  for (const BrdfTable* t : tables_)
    if (!t || !(t->dims() == tables_.front()->dims()))
      throw Error("table combination: the tables must exist and share one grid");
}

Rgb TableCombination::eval(const Vec3& wi, const Vec3& wo) const {
  Rgb f = Rgb::Zero();
  for (std::size_t k = 0; k < tables_.size(); ++k) f += coefficients_[k] * tables_[k]->lookup(wi, wo);
  return f;
}

MaterialList MaterialList::owning(std::vector<std::shared_ptr<const Material>> materials) {
  MaterialList list({});
  for (const auto& m : materials) list.materials_.push_back(m.get());
  list.owned_ = std::move(materials);
  return list;
}

void MaterialList::eval_all(const Vec3& wi, const Vec3& wo, double* out) const {
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const Rgb f = materials_[k]->eval(wi, wo);
    for (int c = 0; c < 3; ++c) out[3 * k + static_cast<std::size_t>(c)] = f[c];
  }
}

}  // namespace matlas::render
