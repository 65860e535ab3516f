#include "server/point_weights.h"

#include <exception>
#include <optional>

namespace matlas::server {

Eigen::VectorXd PointWeights::weights(const Eigen::VectorXd& x, const std::string& key) {
  std::shared_future<Eigen::VectorXd> solved;
  std::optional<std::promise<Eigen::VectorXd>> solve;  // set when this request solves the point
  {
    std::lock_guard lock(mutex_);
    if (const auto* known = points_.find(key)) {
      solved = *known;
    } else {
      solve.emplace();
      solved = solve->get_future().share();
      points_.put(key, solved);
    }
  }
  if (solve) {
    WarmStart warm;
    {
      std::lock_guard lock(mutex_);
      if (!warm_.empty()) {
        warm = std::move(warm_.back());
        warm_.pop_back();
      }
    }
    try {
      solve->set_value(solve_(x, warm));
    } catch (...) {
      solve->set_exception(std::current_exception());
    }
    std::lock_guard lock(mutex_);
    warm_.push_back(std::move(warm));
    if (warm_.size() > kWarmKept) warm_.erase(warm_.begin());
  }
  return solved.get();
}

}  // namespace matlas::server
