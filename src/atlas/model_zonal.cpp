#include "atlas/model_zonal.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

namespace matlas::atlas {

zonal::CoefficientSet model_coefficients(const Model& model, const zonal::ProjectionSettings& settings) {
  const zonal::ZonalProjector projector(settings, model.dims());
  const auto n = static_cast<std::size_t>(model.count());
  const std::size_t bins = model.dims().bins();
  // Table 0 is the mean (weights 0), table 1 + i material i (weights e_i): the model's tables at
  // those weights are exactly mean[column] and z_i[column] (Model::table), so they are read
  // straight from the column-interleaved storage, and only at the quadrature's bins.
  std::vector<zonal::ZonalCoefficients> all = projector.project_many(
      [&](std::uint32_t bin, int channel, double* out) {
        const int column = model.column_of(static_cast<std::size_t>(channel) * bins + bin);
        if (column < 0) {
          std::fill(out, out + n + 1, 0.0);
          return;
        }
        const auto c = static_cast<std::size_t>(column);
        out[0] = model.mean(c);
        if (const float* z = model.data_f32(c)) {
          for (std::size_t i = 0; i < n; ++i) out[1 + i] = z[i];
        } else {
          thread_local std::vector<float> buffer;
          buffer.resize(n);
          model.data(c, buffer.data());
          for (std::size_t i = 0; i < n; ++i) out[1 + i] = buffer[i];
        }
      },
      n + 1);
  zonal::CoefficientSet set;
  set.settings = settings;
  set.names = model.names();
  set.mean = std::move(all[0]);
  set.materials.assign(std::make_move_iterator(all.begin() + 1), std::make_move_iterator(all.end()));
  return set;
}

}  // namespace matlas::atlas
