#pragma once
// PointWeights: the interpolation weights of the latest latent points, each solved once. A step of
// a drag asks for one point several times at once (its preview, its weights and largest
// contributors, slice, lobe, albedo curve, real-time reference), and with convex weights each ask
// is a quadratic programme over the n materials (tens of milliseconds at n = 1000): the first
// request of a point solves it, the others wait for that solve or find it done. The weights are
// those of Model::weights(x), bit for bit (the same x, the same solve). Thread-safe.
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "server/lru_cache.h"

namespace matlas::server {

class PointWeights {
public:
  using Solve = std::function<Eigen::VectorXd(const Eigen::VectorXd& x)>;
  /// Weights by `solve` (the server's: Model::weights), the `capacity` points used last kept.
  explicit PointWeights(Solve solve, std::size_t capacity = 64) : solve_(std::move(solve)), points_(capacity) {}

  /// solve(x), once per point (by its first request; `key` names the point: every coordinate to
  /// 17 digits). A solve's error is every asker's.
  Eigen::VectorXd weights(const Eigen::VectorXd& x, const std::string& key);

private:
  Solve solve_;
  std::mutex mutex_;
  LruCache<std::shared_future<Eigen::VectorXd>> points_;
};

}  // namespace matlas::server
