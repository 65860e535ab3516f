#include "brdf/albedo_operator.h"

#include <vector>

#include "brdf/albedo.h"
#include "core/parallel.h"

namespace matlas {

Eigen::SparseMatrix<double, Eigen::RowMajor> albedo_operator(const MerlDims& dims, int angles,
                                                             int resolution) {
  const std::vector<Vec3> dirs = cosine_quadrature(resolution);
  const double weight = kPi / static_cast<double>(dirs.size());
  std::vector<Eigen::Triplet<double>> entries(dirs.size() * static_cast<std::size_t>(angles));
  parallel_for(0, static_cast<std::size_t>(angles), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t t = lo; t < hi; ++t) {
      const Vec3 wo = direction_at_theta((static_cast<double>(t) + 0.5) / angles * (kPi / 2.0));
      for (std::size_t d = 0; d < dirs.size(); ++d)
        entries[t * dirs.size() + d] = {static_cast<int>(bin_of(dims, dirs[d], wo)), static_cast<int>(t), weight};
    }
  });
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(static_cast<Eigen::Index>(dims.bins()), angles);
  a.setFromTriplets(entries.begin(), entries.end());  // sums duplicates
  return a;
}

}  // namespace matlas
