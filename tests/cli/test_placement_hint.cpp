// The note `matlas build` prints when the exact placement of a large database outweighs the pass.
#include <gtest/gtest.h>

#include "cli/placement_options.h"

namespace matlas::cli {
namespace {

TEST(PlacementHint, OnlyForALargeExactPlacementThatOutweighsThePass) {
  const gp::SparseOptions exact{};
  gp::SparseOptions sparse;
  sparse.inducing = 100;
  // The full-size 1000-material build (docs/BENCHMARKS.md): pass 69 s, exact placement 225 s.
  const std::string hint = placement_hint(1000, exact, 68.68, 224.51);
  EXPECT_NE(hint.find("1000 materials took 225 s against 69 s"), std::string::npos) << hint;
  EXPECT_NE(hint.find("--max-iterations 150 --coarse 300"), std::string::npos) << hint;
  EXPECT_NE(hint.find("--sparse-inducing 100"), std::string::npos) << hint;
  EXPECT_EQ(hint.back(), '\n');
  EXPECT_EQ(placement_hint(1000, sparse, 72.8, 30.4), "") << "already sparse";
  EXPECT_EQ(placement_hint(999, exact, 82.1, 357.8), "") << "the exact placement is the default below 1000";
  EXPECT_EQ(placement_hint(5000, exact, 400.0, 300.0), "") << "the pass dominates: nothing to gain";
}

}  // namespace
}  // namespace matlas::cli
