#include "brdf/albedo_operator.h"

#include <vector>

#include "core/parallel.h"

namespace matlas {

Eigen::SparseMatrix<double, Eigen::RowMajor> albedo_operator(const MerlDims& dims, int angles,
                                                             const AlbedoQuadrature& q) {
  std::vector<std::vector<AlbedoTerm>> rules(static_cast<std::size_t>(angles));
  parallel_for(0, rules.size(), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t t = lo; t < hi; ++t)
      rules[t] = albedo_rule(dims, (static_cast<double>(t) + 0.5) / angles * (kPi / 2.0), q);
  });
  std::size_t total = 0;
  for (const auto& r : rules) total += r.size();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(total);
  for (std::size_t t = 0; t < rules.size(); ++t)
    for (const AlbedoTerm& term : rules[t])
      entries.emplace_back(static_cast<int>(term.bin), static_cast<int>(t), term.weight);
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(static_cast<Eigen::Index>(dims.bins()), angles);
  a.setFromTriplets(entries.begin(), entries.end());  // one entry per (bin, angle) already
  return a;
}

}  // namespace matlas
