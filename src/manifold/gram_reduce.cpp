#include "manifold/gram_reduce.h"

#include <cstring>
#include <numeric>
#include <span>

#include "core/check.h"
#include "core/hash.h"
#include "manifold/gram_update.h"

namespace matlas {

namespace {

void sum_matrix(Eigen::MatrixXd& m, Communicator& comm) {
  comm.sum(std::span<double>(m.data(), static_cast<std::size_t>(m.size())));
}

/// The ranks' compensated Gram sums added up (Communicator::sum_compensated) and rounded again:
/// the single process's value bit for bit (gram_update.h).
void sum_gram(Eigen::MatrixXd& value, Eigen::MatrixXd& low, Communicator& comm) {
  MATLAS_CHECK_EQ(value.size(), low.size());
  comm.sum_compensated(std::span(value.data(), static_cast<std::size_t>(value.size())),
                       std::span(low.data(), static_cast<std::size_t>(low.size())));
  round_compensated(value, low);
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
  sum_gram(g.gram, g.gram_low, comm);
  if (separate_layout_gram) {
    sum_gram(g.layout_gram, g.layout_gram_low, comm);
  } else {
    g.layout_gram = g.gram;
    g.layout_gram_low = g.gram_low;
  }
  sum_matrix(g.albedo, comm);

  // The file hashes of the shares' byte ranges, to rank 0. (The mask and the means stay with
  // their rank, which writes its slices of the model: data_shares.h.)
  const std::vector<std::uint64_t> all_hashes = gather_values(g.hashes, comm);
  if (!comm.is_root()) return kept_per_rank;
  const std::size_t n = g.hashes.size(), ranks = static_cast<std::size_t>(comm.size());
  MATLAS_CHECK_EQ(all_hashes.size(), n * ranks);
  for (std::size_t i = 0; i < n; ++i) {
    Xxh3Hasher parts;
    for (std::size_t r = 0; r < ranks; ++r) parts.update(&all_hashes[r * n + i], sizeof(std::uint64_t));
    g.hashes[i] = parts.digest();
  }
  return kept_per_rank;
}

}  // namespace matlas
