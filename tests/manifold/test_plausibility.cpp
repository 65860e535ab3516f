// PlausibilityProbe: plausible at the inputs; at extrapolated weights its sampled share of
// negative values agrees with an exact count over the whole table, and its albedo range is the
// model's albedo curve.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/check.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "manifold/plausibility.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

/// A model of `count` synthetic materials (q = 2) built in `dir`.
Model small_model(const test::TempDir& dir, int count) {
  test::write_database(dir / "db", count);
  BuildOptions o;
  o.dim = 2;
  build_model(MaterialSet::open({dir / "db"}), o, dir / "m.matlas");
  return Model::open(dir / "m.matlas");
}

TEST(Plausibility, ConvexMixesOfPlausibleInputsArePlausible) {
  // inputs_plausible says whether every input is; when they all are, so is every convex mix (what
  // lets the plausibility layer of a convex model skip its probe). One database of each kind:
  // scaled down, every albedo is below 1; scaled up, some are above.
  for (const double scale : {0.2, 8.0}) {
    test::TempDir dir;
    test::write_database(dir / "db", 6, 1, scale);
    BuildOptions o;
    o.dim = 2;
    build_model(MaterialSet::open({dir / "db"}), o, dir / "m.matlas");
    const Model m = Model::open(dir / "m.matlas");
    const PlausibilityProbe probe(m, 256);
    bool every = true;
    for (int i = 0; i < m.count(); ++i) every = every && probe(m.material_weights(i)).violation() == 0.0;
    EXPECT_EQ(probe.inputs_plausible(), every) << "scale " << scale;
    ASSERT_EQ(every, scale < 1.0) << "scale " << scale << ": the databases are one of each kind";
    if (!every) continue;
    std::mt19937 rng(3);
    std::exponential_distribution<double> e(1.0);
    for (int trial = 0; trial < 50; ++trial) {
      Eigen::VectorXd w(m.count());
      for (int i = 0; i < m.count(); ++i) w[i] = trial % 5 == 0 && i % 2 ? 0.0 : e(rng);
      w /= w.sum();
      EXPECT_EQ(probe(w).violation(), 0.0) << "convex weights " << w.transpose();
    }
  }
}

TEST(Plausibility, InputsArePlausibleAndExtrapolationIsCaught) {
  test::TempDir dir;
  const Model m = small_model(dir, 6);
  const PlausibilityProbe probe(m, 400);
  EXPECT_EQ(probe.samples(), 400u);

  for (int i = 0; i < m.count(); ++i) {
    const Plausibility p = probe(m.material_weights(i));
    EXPECT_EQ(p.negative_fraction, 0.0);
    EXPECT_EQ(p.violation(), std::max(0.0, p.max_albedo - 1.0));
  }

  // Weights far outside the data: a table with many negative values.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m.count());
  for (int i = 0; i < m.count(); ++i) w[i] = i % 2 ? 4.0 : -3.5;
  const BrdfTable table = m.table(w);
  std::size_t negative = 0, kept = 0;
  for (std::size_t v = 0; v < table.size(); ++v) {
    if (!m.kept(v)) continue;
    ++kept;
    negative += m.value(v, w) < 0.0;
  }
  const double exact = static_cast<double>(negative) / static_cast<double>(kept);
  ASSERT_GT(exact, 0.05);
  const Plausibility p = probe(w);
  // Stratified sample of 400: within a few standard errors of the exact share.
  EXPECT_NEAR(p.negative_fraction, exact, 4.0 * std::sqrt(exact * (1 - exact) / 400.0) + 0.01);
  EXPECT_GT(p.violation(), 0.0);

  const auto curve = m.albedo_curve(w);
  double hi = -1e9, lo = 1e9;
  for (const Rgb& a : curve) {
    hi = std::max(hi, a.maxCoeff());
    lo = std::min(lo, a.minCoeff());
  }
  EXPECT_DOUBLE_EQ(p.max_albedo, hi);
  EXPECT_DOUBLE_EQ(p.min_albedo, lo);

  // The batch form (matrix products) agrees with the single form.
  Eigen::MatrixXd W(m.count(), 3);
  W.col(0) = w;
  W.col(1) = m.material_weights(2);
  W.col(2) = m.weights(Eigen::VectorXd(0.5 * (m.latent().row(0) + m.latent().row(3)).transpose()));
  const auto batch = probe.batch(W);
  ASSERT_EQ(batch.size(), 3u);
  for (int j = 0; j < 3; ++j) {
    const Plausibility single = probe(W.col(j));
    EXPECT_NEAR(batch[static_cast<std::size_t>(j)].negative_fraction, single.negative_fraction, 1.0 / 400) << j;
    EXPECT_NEAR(batch[static_cast<std::size_t>(j)].max_albedo, single.max_albedo, 1e-9) << j;
    EXPECT_NEAR(batch[static_cast<std::size_t>(j)].min_albedo, single.min_albedo, 1e-9) << j;
  }
}

/// Runs f, expecting InternalError whose message names `condition`; the message when it does not.
template <class F>
std::string internal_error_of(F&& f) {
  try {
    f();
  } catch (const InternalError& e) {
    return e.what();
  }
  return "no InternalError";
}

TEST(Plausibility, WeightsOfTheWrongLengthAreACallersBug) {
  // A weight vector comes from the model itself (Model::weights, material_weights, a grid's
  // prediction): one of another length is a bug in matlas, refused by a check that names the
  // condition instead of reading past the end of the model's matrices.
  test::TempDir dir;
  const Model m = small_model(dir, 5);
  const PlausibilityProbe probe(m, 50);
  const Eigen::VectorXd wrong = Eigen::VectorXd::Constant(m.count() + 1, 1.0 / (m.count() + 1));
  EXPECT_NE(internal_error_of([&] { probe(wrong); }).find("w.size() == centred_.cols() (6 vs 5)"), std::string::npos)
      << internal_error_of([&] { probe(wrong); });
  EXPECT_NE(internal_error_of([&] { probe.batch(Eigen::MatrixXd::Zero(m.count() - 1, 3)); }).find("W.rows() == centred_.cols()"),
            std::string::npos);
  EXPECT_NE(internal_error_of([&] { m.albedo_curve(wrong); }).find("w.size() == Eigen::Index{count()}"),
            std::string::npos);
  EXPECT_NE(internal_error_of([&] { m.albedo_batch(Eigen::MatrixXd::Zero(m.count() + 2, 4)); }).find("W.rows()"),
            std::string::npos);
  EXPECT_NE(internal_error_of([&] { m.weights_from_gp(wrong, Interpolation::convex); }).find("w.size()"),
            std::string::npos);
  // The right length passes.
  EXPECT_NO_THROW(probe(m.material_weights(0)));
}

}  // namespace
}  // namespace matlas
