// PointWeights: the weights of a latent point solved once however many requests ask for it at
// once, the same values every time, errors given to every asker, the oldest points dropped.
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "server/point_weights.h"

namespace matlas::server {
namespace {

/// A slow solve that counts its calls: w = (x0, 2 x0, 3 x0).
struct CountingSolve {
  std::atomic<int>* calls;
  Eigen::VectorXd operator()(const Eigen::VectorXd& x, PointWeights::WarmStart&) const {
    ++*calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    if (x[0] < 0) throw std::runtime_error("outside the map");
    return Eigen::Vector3d(x[0], 2 * x[0], 3 * x[0]);
  }
};

TEST(PointWeights, ConcurrentRequestsOfOnePointSolveItOnce) {
  std::atomic<int> calls{0};
  PointWeights weights(CountingSolve{&calls});
  const Eigen::VectorXd x = Eigen::Vector2d(0.25, 1.0);
  std::vector<Eigen::VectorXd> got(6);
  std::vector<std::thread> askers;
  for (std::size_t k = 0; k < got.size(); ++k) askers.emplace_back([&, k] { got[k] = weights.weights(x, "a"); });
  for (auto& t : askers) t.join();
  EXPECT_EQ(calls.load(), 1);
  for (const auto& w : got) EXPECT_EQ(w, Eigen::Vector3d(0.25, 0.5, 0.75));
  EXPECT_EQ(weights.weights(x, "a"), got[0]);  // later: found done
  EXPECT_EQ(calls.load(), 1);
  EXPECT_EQ(weights.weights(Eigen::Vector2d(0.5, 1.0), "b"), Eigen::Vector3d(0.5, 1.0, 1.5));
  EXPECT_EQ(calls.load(), 2);
}

TEST(PointWeights, ASolvesErrorReachesEveryAsker) {
  std::atomic<int> calls{0};
  PointWeights weights(CountingSolve{&calls});
  const Eigen::VectorXd x = Eigen::Vector2d(-1.0, 0.0);
  std::atomic<int> errors{0};
  std::vector<std::thread> askers;
  for (int k = 0; k < 3; ++k)
    askers.emplace_back([&] {
      try {
        weights.weights(x, "bad");
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()) == "outside the map") ++errors;
      }
    });
  for (auto& t : askers) t.join();
  EXPECT_EQ(errors.load(), 3);
  EXPECT_EQ(calls.load(), 1);
}

TEST(PointWeights, KeepsOnlyTheLatestPoints) {
  std::atomic<int> calls{0};
  PointWeights weights(CountingSolve{&calls}, 2);
  for (const char* key : {"p", "q", "r"}) weights.weights(Eigen::Vector2d(1.0, 0.0), key);
  EXPECT_EQ(calls.load(), 3);
  weights.weights(Eigen::Vector2d(1.0, 0.0), "r");  // kept
  EXPECT_EQ(calls.load(), 3);
  weights.weights(Eigen::Vector2d(1.0, 0.0), "p");  // dropped: solved again
  EXPECT_EQ(calls.load(), 4);
}

}  // namespace
}  // namespace matlas::server
