#pragma once
// PointWeights: the interpolation weights of the latest latent points, each solved once. A step of
// a drag asks for one point several times at once (its preview, its weights and largest
// contributors, slice, lobe, albedo curve, real-time reference), and with convex weights each ask
// is a quadratic programme over the n materials (tens of milliseconds at n = 1000): the first
// request of a point solves it, the others wait for that solve or find it done. Each solve starts
// from a previous one's state (Model::WarmStart; a drag step moves little, so the
// solution changes little), and the weights are those of Model::weights(x) bit for bit all the
// same (Model::weights(x, warm) settles the solution on its support). Thread-safe.
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "manifold/model.h"
#include "server/lru_cache.h"

namespace matlas::server {

class PointWeights {
public:
  using WarmStart = Model::WarmStart;
  /// solve(x, warm): the weights of x, the solve started from `warm` (a previous solve's state, or
  /// empty), which it leaves holding its own.
  using Solve = std::function<Eigen::VectorXd(const Eigen::VectorXd& x, WarmStart& warm)>;
  /// Weights by `solve` (the server's: Model::weights), the `capacity` points used last kept.
  explicit PointWeights(Solve solve, std::size_t capacity = 64) : solve_(std::move(solve)), points_(capacity) {}

  /// solve(x), once per point (by its first request; `key` names the point: every coordinate to
  /// 17 digits). A solve's error is every asker's.
  Eigen::VectorXd weights(const Eigen::VectorXd& x, const std::string& key);

private:
  Solve solve_;
  std::mutex mutex_;
  LruCache<std::shared_future<Eigen::VectorXd>> points_;
  /// The states of finished solves, the latest last (concurrent solves each take one).
  std::vector<WarmStart> warm_;
  static constexpr std::size_t kWarmKept = 4;
};

}  // namespace matlas::server
