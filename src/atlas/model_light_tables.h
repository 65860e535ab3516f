#pragma once
// The light tables (zonal/light_table.h) of a model's mean and of its n materials as the model
// reconstructs them, kept in float16, and the light table of any map point: their combination
// mean + sum_i w_i (t_i - mean) with the weights' Combination (core/combination.h), as the model's
// own tables combine. What the real-time viewer's direct lights read at the current point
// (POST /api/realtime/lights, docs/API.md).
//
// Built in one pass over the model's column-interleaved data (each column's n values read once);
// 2 bytes per value: (n + 1) x 364,500 values on MERL's grid (0.73 MB per material). A point
// reads the tables of its non-zero weights only (render/basis_kernels.h).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "manifold/model.h"
#include "zonal/light_table.h"

namespace matlas::atlas {

class ModelLightTables {
public:
  /// On the reduced grid of the model's (zonal::LightTable::reduced_dims).
  explicit ModelLightTables(const Model& model);

  int count() const { return n_; }
  const MerlDims& dims() const { return dims_; }
  /// The light table at weights w (length n).
  zonal::LightTable at(const Eigen::Ref<const Eigen::VectorXd>& w) const;
  /// Material i's (i < n) or the mean's (i = n) light table, as stored (float16).
  zonal::LightTable table(int i) const;

private:
  int n_ = 0;
  MerlDims dims_;
  std::size_t size_ = 0;                 ///< values per table: bins x 3
  std::vector<std::uint16_t> values_;    ///< n + 1 rows of size_: the materials', then the mean's
};

}  // namespace matlas::atlas
