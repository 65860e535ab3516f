// The measurement plan: a design whose best direction is known, submodular gains, sequential
// conditioning, and plans that make the fit better than random directions.
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "acquisition/model_samples.h"
#include "acquisition/sample_plan.h"
#include "acquisition_test_model.h"
#include "support/error_of.h"

namespace matlas::acquisition {
namespace {

using test::AcquisitionModel;

/// Candidates where the inputs agree everywhere but at `varying` (plus tiny differences).
PlanSpace plan_space_varying_at(int candidates, int n, int varying) {
  PlanSpace s;
  s.values = Eigen::MatrixXd::Constant(3 * candidates, n, 0.2);
  s.cosine = Eigen::VectorXd::Constant(candidates, 0.5);
  for (int i = 0; i < n; ++i) {
    s.values.middleRows(3 * varying, 3).col(i).setConstant(0.05 + 0.1 * i);
    for (int c = 0; c < candidates; ++c) s.values(3 * c, i) += 1e-4 * ((i * 7 + c * 3) % 5);
  }
  return s;
}

TEST(SamplePlan, PicksTheDirectionWhereTheInputsDiffer) {
  const PlanSpace s = plan_space_varying_at(50, 8, 17);
  const Plan p = plan_directions(s, Eigen::VectorXd::Ones(8), nullptr, 5);
  ASSERT_EQ(p.chosen.size(), 5u);
  EXPECT_EQ(p.chosen.front(), 17);
  EXPECT_EQ(std::set<int>(p.chosen.begin(), p.chosen.end()).size(), 5u);  // never twice
  // Information gain is submodular: the greedy gains never grow; what is left only shrinks.
  for (std::size_t k = 1; k < p.gain.size(); ++k) {
    EXPECT_LE(p.gain[k], p.gain[k - 1] + 1e-9);
    EXPECT_LE(p.remaining[k], p.remaining[k - 1] + 1e-12);
  }
  EXPECT_LT(p.remaining.front(), 0.5);  // the one varying direction explains most of the spread
}

TEST(SamplePlan, AMeasuredDirectionIsWorthLessAndCanBeExcluded) {
  const PlanSpace s = plan_space_varying_at(50, 8, 17);
  const Plan fresh = plan_directions(s, Eigen::VectorXd::Ones(8), nullptr, 1);
  SampleRows measured;
  measured.add(0, s.values.middleRows(3 * 17, 3), Eigen::Array3d::Constant(0.3), Eigen::Array3d::Zero(), 0.5);
  const Plan again = plan_directions(s, Eigen::VectorXd::Ones(8), &measured, 1);
  EXPECT_LT(again.gain.front(), 0.5 * fresh.gain.front());  // what is measured is known
  const int excluded[] = {17};
  const Plan other = plan_directions(s, Eigen::VectorXd::Ones(8), &measured, 1, {}, excluded);
  EXPECT_NE(other.chosen.front(), 17);
}

TEST(SamplePlan, BadArgumentsAreErrors) {
  const PlanSpace s = plan_space_varying_at(10, 4, 1);
  EXPECT_NE(test::error_of([&] { plan_directions(s, Eigen::VectorXd::Ones(3), nullptr, 2); }).find("input weights"),
            std::string::npos);
  EXPECT_NE(test::error_of([&] { plan_directions(s, Eigen::VectorXd::Ones(4), nullptr, 0); }).find("count"),
            std::string::npos);
}

TEST(PlausibleInputs, HaveTheEffectiveCountAskedFor) {
  const Eigen::VectorXd loss = (Eigen::VectorXd(6) << 3.0, 0.5, 9.0, 1.0, 40.0, 2.0).finished();
  for (double want : {1.5, 2.0, 4.0}) {
    const Eigen::VectorXd p = plausible_inputs(loss, want);
    EXPECT_NEAR(p.sum() * p.sum() / p.squaredNorm(), want, 1e-3);
    EXPECT_EQ(std::max_element(p.data(), p.data() + p.size()) - p.data(), 1);  // the best input weighs most
  }
}

TEST(SamplePlan, PlannedDirectionsFitBetterThanRandomOnes) {
  const Model& m = *AcquisitionModel::get().model;
  const ModelPlan plan = plan_samples(m, 6, {}, {});
  ASSERT_EQ(plan.directions.size(), 6u);
  // Several materials off the map, six samples each: planned against random directions.
  double planned = 0, random = 0;
  int k = 0;
  for (auto [a, b] : {std::pair{0.5, 0.5}, std::pair{0.15, 0.9}, std::pair{0.8, 0.2}, std::pair{0.3, 0.6}}) {
    const BrdfTable truth = test::smooth_table(a, b);
    std::vector<MeasuredSample> at_plan = plan.directions;
    for (auto& s : at_plan) {
      const std::size_t bin = bin_of(truth.dims(), s.wi, s.wo);
      for (int c = 0; c < 3; ++c) s.value[c] = truth.value(c, bin);
      s.measured = true;
    }
    planned += test::acquisition_error(m.table(fit_samples(m, at_plan, {}).weights), truth, m);
    for (unsigned seed = 0; seed < 5; ++seed)
      random += test::acquisition_error(
                    m.table(fit_samples(m, test::sample_table(truth, 6, 100 + seed + 10 * static_cast<unsigned>(k)), {}).weights),
                    truth, m) / 5;
    ++k;
  }
  EXPECT_LT(planned, random);
  // The next direction given what was measured is none of those.
  std::vector<MeasuredSample> measured = plan.directions;
  const BrdfTable truth = test::smooth_table(0.5, 0.5);
  for (auto& s : measured) {
    const std::size_t bin = bin_of(truth.dims(), s.wi, s.wo);
    for (int c = 0; c < 3; ++c) s.value[c] = truth.value(c, bin);
    s.measured = true;
  }
  const ModelPlan next = plan_samples(m, 1, measured, {});
  EXPECT_EQ(next.conditioned_on, 6);
  ASSERT_EQ(next.directions.size(), 1u);
  for (const auto& s : plan.directions)
    EXPECT_GT((s.wi - next.directions[0].wi).norm() + (s.wo - next.directions[0].wo).norm(), 1e-9);
}

}  // namespace
}  // namespace matlas::acquisition
