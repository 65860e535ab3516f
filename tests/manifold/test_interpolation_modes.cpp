// The interpolation modes of a model (gp, convex) on databases built to break plausibility: a
// mirror-like material beside a black diffuse one, and a cluster of near-duplicates.
#include <algorithm>
#include <cmath>
#include <map>
#include <thread>

#include <gtest/gtest.h>

#include "gp/likelihood.h"
#include "manifold/build.h"
#include "manifold/model_metadata.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

/// 12 materials: smooth ones, a chrome-like narrow peak 10^3 times brighter, a black diffuse one
/// and four near-duplicates of one smooth material.
std::filesystem::path hostile_database(const std::filesystem::path& dir) {
  test::write_database(dir, 6, 3);
  const MerlDims d = test::kSmallDims;
  BrdfTable chrome(d), black(d);
  for (int i = 0; i < d.theta_h; ++i)
    for (int j = 0; j < d.theta_d; ++j)
      for (int k = 0; k < d.phi_d; ++k)
        for (int c = 0; c < 3; ++c) {
          chrome.set_value(c, d.flat(i, j, k), i == 0 ? 2000.0 * (1 + 0.1 * c) : 1e-3);
          black.set_value(c, d.flat(i, j, k), 0.004 + 0.0005 * c);
        }
  write_merl(dir / "chrome.binary", chrome, true);
  write_merl(dir / "black.binary", black, true);
  for (int m = 0; m < 4; ++m) {
    BrdfTable t = test::smooth_table(0.4, 0.6);
    for (double& v : t.stored()) v *= 1.0 + 0.002 * (m + 1);
    write_merl(dir / ("near-duplicate-" + std::to_string(m) + ".binary"), t, true);
  }
  return dir;
}

struct TableRange {
  double min_value = 0;  ///< smallest kept value of the table
  double max_albedo = 0;
};

TableRange range_of(const Model& m, const Eigen::VectorXd& w) {
  TableRange r{std::numeric_limits<double>::infinity(), 0};
  const BrdfTable t = m.table(w);
  for (std::size_t v = 0; v < t.size(); ++v)
    if (m.kept(v)) r.min_value = std::min(r.min_value, t.stored()[v]);
  for (const Rgb& a : m.albedo_curve(w)) r.max_albedo = std::max({r.max_albedo, a[0], a[1], a[2]});
  return r;
}

/// Dense grid over the latent points' bounding box (which contains their convex hull) plus the
/// midpoints of nearest-neighbour pairs.
std::vector<Eigen::VectorXd> probe_points(const Model& m) {
  std::vector<Eigen::VectorXd> points;
  const Eigen::VectorXd lo = m.latent_min(), hi = m.latent_max();
  const int steps = 40;
  for (int a = 0; a <= steps; ++a)
    for (int b = 0; b <= steps; ++b) {
      Eigen::VectorXd x = 0.5 * (lo + hi);
      x[0] = lo[0] + (hi[0] - lo[0]) * a / steps;
      x[1] = lo[1] + (hi[1] - lo[1]) * b / steps;
      points.push_back(x);
    }
  const Eigen::MatrixXd& X = m.latent();
  for (int i = 0; i < m.count(); ++i) {
    int nearest = -1;
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < m.count(); ++j)
      if (j != i && (X.row(i) - X.row(j)).squaredNorm() < best) best = (X.row(i) - X.row(j)).squaredNorm(), nearest = j;
    points.push_back(0.5 * (X.row(i) + X.row(nearest)).transpose());
  }
  return points;
}

class HostileModel : public ::testing::TestWithParam<int> {
protected:
  void SetUp() override {
    BuildOptions o;
    o.dim = GetParam();
    o.block_columns = 100;
    build_model(MaterialSet::open({hostile_database(dir / "db")}), o, dir / "m.matlas");
  }
  test::TempDir dir;
};

TEST_P(HostileModel, ConvexModeIsPlausibleEverywhereWhereTheGpIsNot) {
  const Model m = Model::open(dir / "m.matlas");
  ASSERT_EQ(m.interpolation(), Interpolation::convex);  // the default
  const double inputs_max_albedo = m.material_albedo().maxCoeff();
  const std::vector<Eigen::VectorXd> points = probe_points(m);
  for (const Eigen::VectorXd& x : points) {
    const Eigen::VectorXd w = m.weights(x);
    ASSERT_GE(w.minCoeff(), 0.0);
    ASSERT_NEAR(w.sum(), 1.0, 1e-12);
    const TableRange r = range_of(m, w);
    ASSERT_GE(r.min_value, 0.0) << "negative value at x = " << x.transpose();
    ASSERT_LE(r.max_albedo, inputs_max_albedo * (1 + 1e-12)) << "energy gain at x = " << x.transpose();
  }
  // The same points with the paper's GP weights: this database does break it (so the test can fail).
  int implausible = 0;
  for (const Eigen::VectorXd& x : points)
    implausible += range_of(m, m.weights(x, Interpolation::gp)).min_value < 0 ? 1 : 0;
  EXPECT_GT(implausible, 0);
}

TEST_P(HostileModel, BothModesReproduceTheInputsExactly) {
  const Model m = Model::open(dir / "m.matlas");
  const MaterialSet set = MaterialSet::open({dir / "db"});
  for (const Interpolation mode : {Interpolation::convex, Interpolation::gp}) {
    for (int i = 0; i < m.count(); ++i) {
      const Eigen::VectorXd w = m.weights(m.latent().row(i).transpose(), mode);
      EXPECT_LT((w - Eigen::VectorXd::Unit(m.count(), i)).cwiseAbs().maxCoeff(), 1e-9) << to_string(mode) << " " << i;
      const BrdfTable input = read_merl(set.file(static_cast<std::size_t>(i)).path());
      const BrdfTable t = m.table(w);
      double worst = 0, peak = 0;
      for (std::size_t v = 0; v < t.size(); ++v)
        if (m.kept(v)) {
          worst = std::max(worst, std::abs(t.stored()[v] - input.stored()[v]));
          peak = std::max(peak, std::abs(input.stored()[v]));
        }
      EXPECT_LE(worst, 1e-6 * peak) << to_string(mode) << " material " << set.name(static_cast<std::size_t>(i));
    }
  }
}

TEST_P(HostileModel, ConvexWeightsAreContinuousAlongADensePath) {
  const Model m = Model::open(dir / "m.matlas");
  // From the chrome-like material through the near-duplicate cluster to the black one.
  const Eigen::VectorXd a = m.latent().row(m.index_of("chrome")).transpose();
  const Eigen::VectorXd b = m.latent().row(m.index_of("near-duplicate-1")).transpose();
  const Eigen::VectorXd c = m.latent().row(m.index_of("black")).transpose();
  auto largest_jump = [&](int steps) {
    Eigen::VectorXd previous = m.weights(a);
    double largest = 0;
    for (int s = 1; s <= steps; ++s) {
      const double t = 2.0 * s / steps;
      const Eigen::VectorXd x = t <= 1 ? Eigen::VectorXd(a + t * (b - a)) : Eigen::VectorXd(b + (t - 1) * (c - b));
      const Eigen::VectorXd w = m.weights(x);
      largest = std::max(largest, (w - previous).cwiseAbs().maxCoeff());
      previous = w;
    }
    return largest;
  };
  // Continuous: ten times finer steps give about ten times smaller jumps (a jump would stay).
  const double coarse = largest_jump(2000), fine = largest_jump(20000);
  EXPECT_LT(fine, 0.25 * coarse + 1e-9) << "the weights jump along the path";
  EXPECT_LT(fine, 0.01);
}

TEST_P(HostileModel, BatchPredictionMatchesSingleQueries) {
  const Model m = Model::open(dir / "m.matlas");
  const std::vector<Eigen::VectorXd> points = probe_points(m);
  Eigen::MatrixXd P(static_cast<Eigen::Index>(points.size()), m.dim());
  for (std::size_t k = 0; k < points.size(); ++k) P.row(static_cast<Eigen::Index>(k)) = points[k].transpose();
  const Model::Prediction batch = m.predict_batch(P);
  for (std::size_t k = 0; k < points.size(); k += 7) {
    EXPECT_LT((batch.weights.col(static_cast<Eigen::Index>(k)) - m.weights(points[k])).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(batch.variance[static_cast<Eigen::Index>(k)], m.variance(points[k]), 1e-9);
  }
}

TEST_P(HostileModel, TheModeIsAParameterOfTheQueryNotStateOfTheModel) {
  const Model m = Model::open(dir / "m.matlas");
  ASSERT_EQ(m.interpolation(), Interpolation::convex);
  const std::vector<Eigen::VectorXd> points = probe_points(m);
  Eigen::MatrixXd P(static_cast<Eigen::Index>(points.size()), m.dim());
  for (std::size_t k = 0; k < points.size(); ++k) P.row(static_cast<Eigen::Index>(k)) = points[k].transpose();
  // The references, one mode after the other on one thread.
  std::map<Interpolation, Eigen::MatrixXd> expected;
  for (const Interpolation mode : {Interpolation::convex, Interpolation::gp}) {
    Eigen::MatrixXd W(m.count(), static_cast<Eigen::Index>(points.size()));
    for (std::size_t k = 0; k < points.size(); ++k) W.col(static_cast<Eigen::Index>(k)) = m.weights(points[k], mode);
    expected[mode] = W;
  }
  ASSERT_GT((expected[Interpolation::convex] - expected[Interpolation::gp]).cwiseAbs().maxCoeff(), 1e-3);
  // Two threads query the one model at once, each in its own mode, by argument and by a handle.
  const Model gp_handle = m.with_interpolation(Interpolation::gp);
  EXPECT_EQ(gp_handle.interpolation(), Interpolation::gp);
  // Single queries are the same function of x on any thread: equal to the bit; the batch (one
  // product, warm-started projections) equal to rounding.
  std::map<Interpolation, double> worst_single{{Interpolation::convex, 0.0}, {Interpolation::gp, 0.0}};
  std::map<Interpolation, double> worst_batch = worst_single;
  auto query = [&](Interpolation mode) {
    const Eigen::MatrixXd& reference = expected.at(mode);
    double& single = worst_single.at(mode);
    for (int round = 0; round < 5; ++round)
      for (std::size_t k = 0; k < points.size(); ++k) {
        const bool by_handle = mode == Interpolation::gp && round % 2 == 1;
        const Eigen::VectorXd w = by_handle ? gp_handle.weights(points[k]) : m.weights(points[k], mode);
        single = std::max(single, (w - reference.col(static_cast<Eigen::Index>(k))).cwiseAbs().maxCoeff());
      }
    worst_batch.at(mode) = (m.predict_batch(P, mode).weights - reference).cwiseAbs().maxCoeff();
  };
  std::thread convex([&] { query(Interpolation::convex); }), gp([&] { query(Interpolation::gp); });
  convex.join();
  gp.join();
  for (const Interpolation mode : {Interpolation::convex, Interpolation::gp}) {
    EXPECT_EQ(worst_single.at(mode), 0.0) << to_string(mode);
    EXPECT_LT(worst_batch.at(mode), 1e-9) << to_string(mode);
  }
  // Neither the handle nor the queries changed the model's own default.
  EXPECT_EQ(m.interpolation(), Interpolation::convex);
  EXPECT_LT((m.weights(points[0]) - expected[Interpolation::convex].col(0)).cwiseAbs().maxCoeff(), 1e-15);
}

TEST_P(HostileModel, DistinctMaterialsStayApartOnTheMap) {
  // The near-duplicates differ by 0.2 % and the likelihood alone would merge them; the repulsive
  // prior keeps every pair at a readable distance.
  const Model m = Model::open(dir / "m.matlas");
  const Eigen::MatrixXd& X = m.latent();
  const double extent = (X.colwise().maxCoeff() - X.colwise().minCoeff()).norm();
  for (int i = 0; i < m.count(); ++i)
    for (int j = i + 1; j < m.count(); ++j)
      EXPECT_GT((X.row(i) - X.row(j)).norm(), 0.01 * extent) << m.names()[static_cast<std::size_t>(i)] << " / "
                                                             << m.names()[static_cast<std::size_t>(j)];
}

INSTANTIATE_TEST_SUITE_P(Dims, HostileModel, ::testing::Values(2, 3));

TEST(PaperPreset, IsThePlainGpLikelihoodWithGpWeights) {
  test::TempDir dir;
  test::write_database(dir / "db", 8, 5);
  BuildOptions o = BuildOptions::paper_preset();
  o.dim = 2;
  EXPECT_TRUE(o.prior.is_off());
  EXPECT_EQ(o.nugget, 1e-4);
  EXPECT_EQ(o.optimize.method, gp::Optimizer::hooke_jeeves);
  EXPECT_EQ(o.layout.to_string(), "linear");
  // All at once with up to 5000 sweeps at any size: the build's automatic choices are not the paper's.
  EXPECT_EQ(o.optimize.resolved(1000).max_iterations, 5000);
  EXPECT_EQ(o.optimize.resolved(1000).coarse, 0);
  EXPECT_EQ(BuildOptions{}.optimize.resolved(1000).coarse, 300);
  build_model(MaterialSet::open({dir / "db"}), o, dir / "m.matlas");
  const Model m = Model::open(dir / "m.matlas");
  EXPECT_EQ(m.interpolation(), Interpolation::gp);
  EXPECT_EQ(m.metadata().at("interpolation").at("mode"), "gp");
  // Its weights are the posterior's, of any sign, and its stored likelihood the plain one.
  const Eigen::Vector2d x = 0.5 * (m.latent().row(0) + m.latent().row(1)).transpose() + Eigen::Vector2d(0.7, -0.4);
  EXPECT_LT((m.weights(x) - m.posterior().weights(x)).cwiseAbs().maxCoeff(), 1e-15);
  gp::LikelihoodProblem p;
  p.gram = m.gram();
  p.columns = static_cast<double>(m.kept_columns());
  p.kernel = gp::Kernel{1.0, 1e-4};
  EXPECT_NEAR(m.metadata().at("log_likelihood").get<double>(), gp::log_likelihood(p, m.latent()),
              1e-9 * std::abs(gp::log_likelihood(p, m.latent())));
}

}  // namespace
}  // namespace matlas
