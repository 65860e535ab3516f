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
    try {
      solve->set_value(solve_(x));
    } catch (...) {
      solve->set_exception(std::current_exception());
    }
  }
  return solved.get();
}

}  // namespace matlas::server
