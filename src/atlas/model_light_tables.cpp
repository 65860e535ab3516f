#include "atlas/model_light_tables.h"

#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "core/check.h"
#include "core/combination.h"
#include "core/error.h"
#include "core/parallel.h"
#include "formats/half_float.h"
#include "render/basis_kernels.h"

namespace matlas::atlas {

ModelLightTables::ModelLightTables(const Model& model) : n_(model.count()) {
  const MerlDims& full = model.dims();
  dims_ = zonal::LightTable::reduced_dims(full);
  size_ = dims_.bins() * 3;
  const auto rows = static_cast<std::size_t>(n_) + 1;
  values_.assign(rows * size_, 0);
  const int group = full.phi_d / dims_.phi_d;
  const auto phi = static_cast<std::size_t>(dims_.phi_d);
  const std::size_t bins = full.bins();
  // Each theta_h row of every table in one task: its columns' n values read once.
  parallel_for_each(0, static_cast<std::size_t>(full.theta_h), [&](std::size_t row) {
    const int i = static_cast<int>(row);
    std::vector<float> buffer(static_cast<std::size_t>(n_));
    std::vector<double> sum(rows);
    // Per table: the values of this row (missing: NaN), filled below as LightTable::reduce does.
    std::vector<float> out(rows * static_cast<std::size_t>(full.theta_d) * phi * 3,
                           std::numeric_limits<float>::quiet_NaN());
    const std::size_t per_row = static_cast<std::size_t>(full.theta_d) * phi * 3;
    for (int j = 0; j < full.theta_d; ++j)
      for (int k = 0; k < static_cast<int>(phi); ++k)
        for (int c = 0; c < 3; ++c) {
          std::fill(sum.begin(), sum.end(), 0.0);
          int count = 0;
          for (int e = 0; e < group; ++e) {
            const int column = model.column_of(static_cast<std::size_t>(c) * bins + full.flat(i, j, k * group + e));
            if (column < 0) continue;
            const auto col = static_cast<std::size_t>(column);
            model.data(col, buffer.data());
            for (std::size_t m = 0; m < static_cast<std::size_t>(n_); ++m) sum[m] += buffer[m];
            sum[rows - 1] += model.mean(col);
            ++count;
          }
          if (!count) continue;
          const std::size_t at = (static_cast<std::size_t>(j) * phi + static_cast<std::size_t>(k)) * 3 +
                                 static_cast<std::size_t>(c);
          for (std::size_t m = 0; m < rows; ++m) out[m * per_row + at] = static_cast<float>(sum[m] / count);
        }
    for (std::size_t m = 0; m < rows; ++m)
      for (std::size_t v = 0; v < per_row; ++v)
        values_[m * size_ + row * per_row + v] = float_to_half(out[m * per_row + v]);
  });
  // Missing values: the nearest measured one below in theta_h (0 without one), per table.
  const std::size_t per_row = static_cast<std::size_t>(dims_.theta_d) * dims_.phi_d * 3;
  parallel_for_each(0, rows, [&](std::size_t m) {
    std::uint16_t* t = values_.data() + m * size_;
    for (std::size_t v = 0; v < per_row; ++v) {
      std::uint16_t last = 0;
      for (int i = 0; i < dims_.theta_h; ++i) {
        std::uint16_t& x = t[static_cast<std::size_t>(i) * per_row + v];
        if (std::isnan(half_to_float(x))) x = last;
        else last = x;
      }
    }
  });
}

zonal::LightTable ModelLightTables::table(int i) const {
  MATLAS_CHECK(i >= 0 && i <= n_);
  zonal::LightTable t(dims_);
  const std::uint16_t* row = values_.data() + static_cast<std::size_t>(i) * size_;
  for (std::size_t v = 0; v < size_; ++v) t.values()[v] = half_to_float(row[v]);
  return t;
}

zonal::LightTable ModelLightTables::at(const Eigen::Ref<const Eigen::VectorXd>& w) const {
  if (w.size() != n_) throw Error("light tables: " + std::to_string(w.size()) + " weights for " + std::to_string(n_) + " materials");
  const Eigen::VectorXd a = Combination(w).coefficients();  // (mean, inputs)
  std::vector<int> rows;
  std::vector<float> weights;
  if (a[0] != 0.0) {
    rows.push_back(n_);
    weights.push_back(static_cast<float>(a[0]));
  }
  for (int i = 0; i < n_; ++i)
    if (a[i + 1] != 0.0) {
      rows.push_back(i);
      weights.push_back(static_cast<float>(a[i + 1]));
    }
  zonal::LightTable t(dims_);
  std::vector<float>& acc = t.values();
  parallel_for(0, size_, [&](std::size_t begin, std::size_t end) {
    render::detail::accumulate_f16(values_.data(), size_, begin, end - begin, rows.data(), weights.data(),
                                   static_cast<int>(rows.size()), acc.data() + begin);
  }, 4096);
  return t;
}

}  // namespace matlas::atlas
