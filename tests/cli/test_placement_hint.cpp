// The note `matlas build` prints when the exact placement of a large database outweighs the pass.
#include <gtest/gtest.h>

#include "cli/placement_options.h"

namespace matlas::cli {
namespace {

TEST(PlacementHint, OnlyForALargeExactPlacementThatOutweighsThePass) {
  const gp::SparseOptions exact{};
  gp::SparseOptions sparse;
  sparse.inducing = 100;
  // The full-size 1000-material build with --max-iterations 5000 --coarse 0: pass 69 s, exact placement 225 s.
  const std::string hint = placement_hint(1000, exact, 68.68, 224.51);
  EXPECT_NE(hint.find("1000 materials took 225 s against 69 s"), std::string::npos) << hint;
  EXPECT_NE(hint.find("automatic --max-iterations and --coarse (leave them out)"), std::string::npos) << hint;
  EXPECT_NE(hint.find("--sparse-inducing 100"), std::string::npos) << hint;
  EXPECT_EQ(hint.back(), '\n');
  EXPECT_EQ(placement_hint(1000, sparse, 72.8, 30.4), "") << "already sparse";
  EXPECT_NE(placement_hint(500, exact, 20.0, 30.0), "") << "from 500 materials on, the automatic choices cut it";
  EXPECT_EQ(placement_hint(499, exact, 20.0, 30.0), "") << "below 500 the whole placement is the default";
  EXPECT_EQ(placement_hint(5000, exact, 400.0, 300.0), "") << "the pass dominates: nothing to gain";
}

TEST(ConvergenceMessage, ANoteForTheAutomaticLimitOfALargeDatabaseElseAWarning) {
  gp::OptimizeResult stopped;
  stopped.stop_reason = "iteration limit reached";
  const std::string note = convergence_message(1000, -1, stopped);
  EXPECT_EQ(note.rfind("note: the latent placement of 1000 materials stopped at its automatic limit", 0), 0u) << note;
  EXPECT_NE(note.find("a refinement of 100 iterations"), std::string::npos) << note;  // 10^11 / 1000^3
  EXPECT_EQ(convergence_message(1000, 5000, stopped).rfind("warning: the latent placement did not converge", 0), 0u)
      << "a limit the user set";
  EXPECT_EQ(convergence_message(499, -1, stopped).rfind("warning:", 0), 0u) << "5000 iterations below 500 materials";
  gp::OptimizeResult timed = stopped;
  timed.stop_reason = "time limit reached";
  EXPECT_EQ(convergence_message(1000, -1, timed).rfind("warning:", 0), 0u);
  gp::OptimizeResult converged;
  converged.stop_reason = "converged: gradient norm below tolerance";
  EXPECT_EQ(convergence_message(1000, -1, converged), "");
}

}  // namespace
}  // namespace matlas::cli
