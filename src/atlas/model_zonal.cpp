#include "atlas/model_zonal.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <vector>

#include "core/check.h"
#include "core/parallel.h"

namespace matlas::atlas {

namespace {

/// One material's coefficients as doubles: bands, T, lobe count, values, lobes.
std::vector<double> flatten(const zonal::ZonalCoefficients& c) {
  std::vector<double> out{static_cast<double>(c.bands), static_cast<double>(c.theta_o_count),
                          static_cast<double>(c.lobes.size())};
  out.insert(out.end(), c.values.begin(), c.values.end());
  out.insert(out.end(), c.lobes.begin(), c.lobes.end());
  return out;
}

zonal::ZonalCoefficients unflatten(const std::vector<double>& v) {
  MATLAS_CHECK_GE(v.size(), std::size_t{3});
  zonal::ZonalCoefficients c;
  c.bands = static_cast<int>(v[0]);
  c.theta_o_count = static_cast<int>(v[1]);
  const auto lobes = static_cast<std::size_t>(v[2]);
  MATLAS_CHECK_GE(v.size(), 3 + lobes);
  c.values.assign(v.begin() + 3, v.end() - static_cast<std::ptrdiff_t>(lobes));
  c.lobes.assign(v.end() - static_cast<std::ptrdiff_t>(lobes), v.end());
  return c;
}

/// Every rank's coefficients (its share, in order) on rank 0; empty elsewhere.
std::vector<zonal::ZonalCoefficients> gather_coefficients(std::vector<zonal::ZonalCoefficients> mine,
                                                          Communicator& comm) {
  if (comm.size() == 1) return mine;
  std::vector<std::vector<double>> flat;
  for (const auto& c : mine) flat.push_back(flatten(c));
  std::vector<zonal::ZonalCoefficients> all;
  for (const auto& v : gather_arrays(comm, flat)) all.push_back(unflatten(v));
  return all;
}

}  // namespace

zonal::CoefficientSet model_coefficients(const Model& model, const zonal::ProjectionSettings& settings,
                                         Communicator& comm) {
  const zonal::ZonalProjector projector(settings, model.dims());
  const auto n = static_cast<std::size_t>(model.count());
  const std::size_t bins = model.dims().bins();
  // Table 0 is the mean (weights 0), table 1 + i material i (weights e_i): the model's tables at
  // those weights are exactly mean[column] and z_i[column] (Model::table), so they are read
  // straight from the column-interleaved storage, and only at the quadrature's bins. This rank
  // projects tables [first, last).
  const auto share = share_of(n + 1, comm.rank(), comm.size());
  const std::size_t first = share.first, last = share.second;
  std::vector<zonal::ZonalCoefficients> mine;
  run_collectively(comm, [&] {
    if (first == last) return;
    mine = projector.project_many(
        [&](std::uint32_t bin, int channel, double* out) {
          const int column = model.column_of(static_cast<std::size_t>(channel) * bins + bin);
          if (column < 0) {
            std::fill(out, out + (last - first), 0.0);
            return;
          }
          const auto c = static_cast<std::size_t>(column);
          thread_local std::vector<float> buffer;
          const float* z = model.data_f32(c);
          if (!z) {
            buffer.resize(n);
            model.data(c, buffer.data());
            z = buffer.data();
          }
          for (std::size_t k = first; k < last; ++k) out[k - first] = k == 0 ? model.mean(c) : z[k - 1];
        },
        last - first);
  });
  std::vector<zonal::ZonalCoefficients> all = gather_coefficients(std::move(mine), comm);
  zonal::CoefficientSet set;
  set.settings = settings;
  set.names = model.names();
  if (!comm.is_root()) return set;
  MATLAS_CHECK_EQ(all.size(), n + 1);
  set.mean = std::move(all[0]);
  set.materials.assign(std::make_move_iterator(all.begin() + 1), std::make_move_iterator(all.end()));
  return set;
}

zonal::CoefficientSet database_coefficients(const MaterialSet& set, const zonal::ProjectionSettings& settings,
                                            Communicator& comm, ProgressSink& progress) {
  const zonal::ZonalProjector projector(settings, set.dims());
  const auto [first, last] = share_of(set.size(), comm.rank(), comm.size());
  std::vector<zonal::ZonalCoefficients> mine(last - first);
  run_collectively(comm, [&, first = first, last = last] {
    ProgressTask task(progress, "projecting tables", last - first);
    for (std::size_t i = first; i < last; ++i) {
      const MerlFile& file = set.file(i);
      BrdfTable table(file.dims(), ValueBuffer::Uninitialized{});
      file.read_values(0, file.value_count(), table.stored().data());
      mine[i - first] = projector.project(table);
      task.advance(1);
    }
  });
  zonal::CoefficientSet out;
  out.settings = settings;
  out.names = set.names();
  out.materials = gather_coefficients(std::move(mine), comm);
  return out;
}

}  // namespace matlas::atlas
