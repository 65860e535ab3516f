#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/error.h"
#include "gp/initialize.h"
#include "gp/optimize.h"
#include "gp_test_data.h"

namespace matlas::gp {
namespace {

LikelihoodProblem small_problem() {
  LikelihoodProblem p = test::problem_for(test::random_low_rank_data(12, 50, 3, 77));
  p.columns = 4.37e6;
  return p;
}

OptimizeResult run(const LikelihoodProblem& p, const Eigen::MatrixXd& X0, Optimizer method, double tolerance = 1e-9,
                   int max_iterations = 5000) {
  OptimizeOptions o;
  o.method = method;
  o.tolerance = tolerance;
  o.max_iterations = max_iterations;
  return optimize_latent(p, X0, o, null_progress());
}

// Pairwise distances: invariant to the rotations and translations the likelihood ignores.
Eigen::MatrixXd distances(const Eigen::MatrixXd& X) {
  Eigen::MatrixXd D(X.rows(), X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index j = 0; j < X.rows(); ++j) D(i, j) = (X.row(i) - X.row(j)).norm();
  return D;
}

TEST(Optimize, BothMethodsIncreaseTheLikelihoodAndLbfgsReachesHookeJeeves) {
  const LikelihoodProblem p = small_problem();
  const Eigen::MatrixXd X0 = pca_initialization(p, 2);
  const double L0 = log_likelihood(p, X0);
  const OptimizeResult lbfgs = run(p, X0, Optimizer::lbfgs);
  const OptimizeResult hj = run(p, X0, Optimizer::hooke_jeeves, 1e-8);
  EXPECT_GT(lbfgs.value, L0);
  EXPECT_GT(hj.value, L0);
  // Values are ~1e8 here; "tiny" = 1e-9 relative.
  EXPECT_GE(lbfgs.value, hj.value - 1e-9 * std::abs(hj.value)) << lbfgs.stop_reason << " / " << hj.stop_reason;
  EXPECT_EQ(lbfgs.value, log_likelihood(p, lbfgs.latent));
  EXPECT_EQ(hj.value, log_likelihood(p, hj.latent));
  EXPECT_EQ(lbfgs.history.front(), L0);
  EXPECT_EQ(lbfgs.history.back(), lbfgs.value);
  EXPECT_TRUE(std::is_sorted(lbfgs.history.begin(), lbfgs.history.end()));
  EXPECT_TRUE(std::is_sorted(hj.history.begin(), hj.history.end()));
  EXPECT_GT(lbfgs.iterations, 0);
  EXPECT_GT(hj.evaluations, lbfgs.evaluations);
  EXPECT_EQ(lbfgs.stop_reason.rfind("converged", 0), 0u) << lbfgs.stop_reason;
  // At the L-BFGS optimum the gradient is small relative to its size at the start.
  Eigen::MatrixXd g0, g1;
  log_likelihood(p, X0, &g0);
  log_likelihood(p, lbfgs.latent, &g1);
  EXPECT_LT(g1.norm(), 1e-3 * g0.norm());
}

TEST(Optimize, ScalingTheDataGivesTheSameLatentPoints) {
  const LikelihoodProblem p = small_problem();
  LikelihoodProblem scaled = p;
  const double c = 1e6;
  scaled.gram *= c;
  const OptimizeResult a = run(p, pca_initialization(p, 3), Optimizer::lbfgs);
  const OptimizeResult b = run(scaled, pca_initialization(scaled, 3), Optimizer::lbfgs);
  const Eigen::MatrixXd Da = distances(a.latent), Db = distances(b.latent);
  EXPECT_LT((Da - Db).cwiseAbs().maxCoeff(), 1e-4 * Da.maxCoeff());
  EXPECT_NEAR(b.value - a.value, -12.0 * p.columns * std::log(c), 1e-9 * std::abs(a.value));
}

TEST(Optimize, IsDeterministic) {
  const LikelihoodProblem p = small_problem();
  const Eigen::MatrixXd X0 = pca_initialization(p, 2);
  for (Optimizer m : {Optimizer::lbfgs, Optimizer::hooke_jeeves}) {
    const OptimizeResult a = run(p, X0, m, 1e-6), b = run(p, X0, m, 1e-6);
    EXPECT_EQ(a.latent, b.latent) << to_string(m);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.history, b.history);
    EXPECT_EQ(a.evaluations, b.evaluations);
  }
}

TEST(Optimize, RecoversTheOrderOfOneDimensionalLatentPoints) {
  const int n = 15;
  Eigen::VectorXd t(n);
  for (int i = 0; i < n; ++i) t[i] = 0.25 * i + 0.05 * std::sin(3.0 * i);  // irregular spacing
  // Shuffle the items so that the order is not the storage order.
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  for (int i = 0; i < n; ++i) std::swap(perm[i], perm[(7 * i + 3) % n]);
  Eigen::VectorXd shuffled(n);
  for (int i = 0; i < n; ++i) shuffled[i] = t[perm[i]];
  LikelihoodProblem p = test::problem_for(test::curve_data(shuffled, 30, 5));
  p.kernel.nugget = 1e-3;
  const OptimizeResult r = run(p, pca_initialization(p, 1), Optimizer::lbfgs);
  // Sort items by the recovered coordinate: their true t must be monotone.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return r.latent(a, 0) < r.latent(b, 0); });
  std::vector<double> t_sorted;
  for (int i : order) t_sorted.push_back(shuffled[i]);
  const bool increasing = std::is_sorted(t_sorted.begin(), t_sorted.end());
  const bool decreasing = std::is_sorted(t_sorted.rbegin(), t_sorted.rend());
  EXPECT_TRUE(increasing || decreasing) << r.latent.transpose();
}

TEST(Optimize, StopsAtLimitsAndTargets) {
  const LikelihoodProblem p = small_problem();
  const Eigen::MatrixXd X0 = pca_initialization(p, 2);
  const OptimizeResult three = run(p, X0, Optimizer::lbfgs, 1e-12, 3);
  EXPECT_EQ(three.iterations, 3);
  EXPECT_EQ(three.stop_reason, "iteration limit reached");
  const OptimizeResult none = run(p, X0, Optimizer::hooke_jeeves, 1e-12, 0);
  EXPECT_EQ(none.latent, X0);
  EXPECT_EQ(none.evaluations, 1);

  const OptimizeResult full = run(p, X0, Optimizer::lbfgs);
  OptimizeOptions o;
  o.target_value = 0.5 * (full.history.front() + full.value);
  const OptimizeResult targeted = optimize_latent(p, X0, o, null_progress());
  EXPECT_EQ(targeted.stop_reason, "target value reached");
  EXPECT_GE(targeted.value, o.target_value);
  EXPECT_LT(targeted.evaluations, full.evaluations);
  o.target_value = full.history.front();  // already reached at X0
  const OptimizeResult at_start = optimize_latent(p, X0, o, null_progress());
  EXPECT_EQ(at_start.stop_reason, "target value reached");
  EXPECT_EQ(at_start.evaluations, 1);
  EXPECT_EQ(at_start.latent, X0);
}

TEST(Optimize, ReportsProgressAndRejectsBadInput) {
  struct Recorder final : ProgressSink {
    std::vector<std::string> lines;
    void update(const std::string&, std::uint64_t, std::uint64_t) override {}
    void message(const std::string& line) override { lines.push_back(line); }
    void finish(const std::string&) override {}
  } sink;
  const LikelihoodProblem p = small_problem();
  OptimizeOptions o;
  optimize_latent(p, pca_initialization(p, 2), o, sink);
  ASSERT_GE(sink.lines.size(), 2u);
  EXPECT_NE(sink.lines.front().find("iter 0  L = "), std::string::npos) << sink.lines.front();
  EXPECT_NE(sink.lines.back().find("stopped"), std::string::npos) << sink.lines.back();
  EXPECT_THROW(optimize_latent(p, Eigen::MatrixXd::Zero(11, 2), o, null_progress()), Error);
  Eigen::MatrixXd bad = pca_initialization(p, 2);
  bad(0, 0) = std::nan("");
  EXPECT_THROW(optimize_latent(p, bad, o, null_progress()), Error);
}

TEST(Optimize, MultipleStartsKeepTheBest) {
  // q = 1 on 2-D data: a multimodal case where the spread of the start matters.
  const LikelihoodProblem p = test::problem_for(test::random_low_rank_data(14, 30, 2, 5));
  const Eigen::MatrixXd X0 = pca_initialization(p, 1);
  OptimizeOptions o;
  o.starts = 5;
  const OptimizeResult multi = optimize_latent(p, X0, o, null_progress());
  EXPECT_EQ(multi.value, log_likelihood(p, multi.latent));
  EXPECT_GE(multi.best_start, 0);
  EXPECT_LT(multi.best_start, 5);
  EXPECT_NE(multi.stop_reason.find("best of 5 starts"), std::string::npos) << multi.stop_reason;
  // Each start alone, from X0 scaled about its centroid by 1, 2^-1/2, 2^1/2, 2^-1, 2^1.
  const double scales[] = {1.0, std::sqrt(0.5), std::sqrt(2.0), 0.5, 2.0};
  double best = -std::numeric_limits<double>::infinity();
  int evaluations = 0;
  const Eigen::RowVectorXd centroid = X0.colwise().mean();
  for (double s : scales) {
    const Eigen::MatrixXd start = (s * (X0.rowwise() - centroid)).rowwise() + centroid;
    const OptimizeResult one = run(p, start, Optimizer::lbfgs, o.tolerance, o.max_iterations);
    best = std::max(best, one.value);
    evaluations += one.evaluations;
  }
  EXPECT_EQ(multi.value, best);
  EXPECT_EQ(multi.evaluations, evaluations);
  o.starts = 0;
  EXPECT_THROW(optimize_latent(p, X0, o, null_progress()), Error);
}

TEST(Optimize, NamesRoundTrip) {
  for (Optimizer m : {Optimizer::lbfgs, Optimizer::hooke_jeeves}) EXPECT_EQ(optimizer_from_string(to_string(m)), m);
  EXPECT_EQ(optimizer_from_string("hj"), Optimizer::hooke_jeeves);
  EXPECT_THROW(optimizer_from_string("newton"), Error);
}

TEST(OptimizeLatent, PriorsKeepNearDuplicatesApartAndTheExtentBounded) {
  // Three near-identical materials among 20: the plain likelihood merges them into one point
  // (and can fling others far away); the MAP placement keeps them apart at about the repulsion
  // radius and the layout compact.
  for (const std::uint64_t seed : {40u, 41u, 42u}) {
    Eigen::MatrixXd Z = test::random_low_rank_data(20, 50, 4, seed);
    Z.row(1) = Z.row(0) + 1e-4 * Z.row(1);
    Z.row(2) = Z.row(0) + 1e-4 * Z.row(2);
    LikelihoodProblem p = test::problem_for(Z, 1e5);
    p.kernel = Kernel{1.0, 1e-4};
    const Eigen::MatrixXd X0 = pca_initialization(p, 2);
    auto closest = [](const Eigen::MatrixXd& X) {
      return std::min({(X.row(0) - X.row(1)).norm(), (X.row(0) - X.row(2)).norm(), (X.row(1) - X.row(2)).norm()});
    };
    auto extent = [](const Eigen::MatrixXd& X) { return (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm(); };
    const OptimizeResult plain = optimize_latent(p, X0, OptimizeOptions{}, null_progress());
    p.prior = LatentPrior::spread();
    const OptimizeResult map = optimize_latent(p, X0, OptimizeOptions{}, null_progress());
    EXPECT_TRUE(map.converged()) << map.stop_reason;
    EXPECT_LT(closest(plain.latent), 1e-3) << "seed " << seed;
    EXPECT_GT(closest(map.latent), 0.025) << "seed " << seed;  // a quarter of the radius, 10^4 x the plain fit
    EXPECT_LT(extent(map.latent), 8.0) << "seed " << seed;
  }
}

}  // namespace
}  // namespace matlas::gp
