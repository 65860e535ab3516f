#include "brdf/albedo_operator.h"

#include <vector>

#include "brdf/albedo.h"

namespace matlas {

Eigen::SparseMatrix<double, Eigen::RowMajor> albedo_operator(const MerlDims& dims, int angles,
                                                             int resolution) {
  const std::vector<Vec3> dirs = cosine_quadrature(resolution);
  const double weight = kPi / static_cast<double>(dirs.size());
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(dirs.size() * static_cast<std::size_t>(angles));
  for (int t = 0; t < angles; ++t) {
    const Vec3 wo = direction_at_theta((t + 0.5) / angles * (kPi / 2.0));
    for (const Vec3& wi : dirs)
      entries.emplace_back(static_cast<int>(bin_of(dims, wi, wo)), t, weight);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(static_cast<Eigen::Index>(dims.bins()), angles);
  a.setFromTriplets(entries.begin(), entries.end());  // sums duplicates
  return a;
}

}  // namespace matlas
