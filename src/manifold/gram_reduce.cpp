#include "manifold/gram_reduce.h"

#include <cstring>
#include <numeric>
#include <span>

#include "core/check.h"
#include "core/hash.h"

namespace matlas {

namespace {

void sum_matrix(Eigen::MatrixXd& m, Communicator& comm) {
  comm.sum(std::span<double>(m.data(), static_cast<std::size_t>(m.size())));
}

template <class T>
std::vector<T> gather_values(const std::vector<T>& mine, Communicator& comm) {
  const std::vector<std::byte> all = comm.gather(std::as_bytes(std::span<const T>(mine)));
  MATLAS_CHECK_EQ(all.size() % sizeof(T), std::size_t{0});
  std::vector<T> out(all.size() / sizeof(T));
  if (!all.empty()) std::memcpy(out.data(), all.data(), all.size());
  return out;
}

}  // namespace

std::vector<std::uint64_t> reduce_gram(GramResult& g, bool separate_layout_gram, Communicator& comm) {
  std::vector<std::uint64_t> kept_per_rank = comm.all_gather(g.kept_columns);
  if (comm.size() == 1) {
    require_kept_columns(g);
    return kept_per_rank;
  }
  g.kept_columns = std::accumulate(kept_per_rank.begin(), kept_per_rank.end(), std::size_t{0});
  require_kept_columns(g);
  sum_matrix(g.gram, comm);
  if (separate_layout_gram) sum_matrix(g.layout_gram, comm);
  else g.layout_gram = g.gram;
  sum_matrix(g.albedo, comm);

  // The share's mask, means and hashes, to rank 0.
  std::vector<std::uint8_t> kept(g.kept.begin() + static_cast<std::ptrdiff_t>(g.first_value),
                                 g.kept.begin() + static_cast<std::ptrdiff_t>(g.end_value));
  const std::vector<std::uint8_t> all_kept = gather_values(kept, comm);
  const std::vector<double> mean(g.mean.data(), g.mean.data() + g.mean.size());
  const std::vector<double> all_mean = gather_values(mean, comm);
  const std::vector<std::uint64_t> all_hashes = gather_values(g.hashes, comm);
  if (!comm.is_root()) return kept_per_rank;

  MATLAS_CHECK_EQ(all_kept.size(), g.kept.size());  // the shares cover every column
  MATLAS_CHECK_EQ(all_mean.size(), g.kept_columns);  // one mean per kept column
  const std::size_t n = g.hashes.size(), ranks = static_cast<std::size_t>(comm.size());
  MATLAS_CHECK_EQ(all_hashes.size(), n * ranks);
  g.first_value = 0;
  g.end_value = all_kept.size();
  for (std::size_t v = 0; v < all_kept.size(); ++v) g.kept[v] = all_kept[v] != 0;
  g.mean = Eigen::Map<const Eigen::VectorXd>(all_mean.data(), static_cast<Eigen::Index>(all_mean.size()));
  for (std::size_t i = 0; i < n; ++i) {
    Xxh3Hasher parts;
    for (std::size_t r = 0; r < ranks; ++r) parts.update(&all_hashes[r * n + i], sizeof(std::uint64_t));
    g.hashes[i] = parts.digest();
  }
  return kept_per_rank;
}

}  // namespace matlas
