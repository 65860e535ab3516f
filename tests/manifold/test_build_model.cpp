// Building a model and querying it, against explicit computations on the input tables.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>
#include <xxhash.h>

#include "brdf/albedo.h"
#include "core/error.h"
#include "manifold/build.h"
#include "manifold/export.h"
#include "manifold/model_metadata.h"
#include "manifold/project.h"
#include "support/error_of.h"
#include "support/temp_dir.h"
#include "synthetic_database.h"

namespace matlas {
namespace {

using test::TempDir;

BuildOptions small_options(int q = 2) {
  BuildOptions o;
  o.dim = q;
  o.block_columns = 100;  // many blocks even on the small grid
  return o;
}

using test::error_of;

using test::relative_l2;

class BuiltModel : public ::testing::Test {
protected:
  void SetUp() override {
    paths = test::write_database(dir / "db", 12);
    // One material lacks a measurement in one column: that column is dropped for everyone.
    BrdfTable t = read_merl(paths[3]);
    t.set_missing(1, 17);
    write_merl(paths[3], t, true);
    report = build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "m.matlas");
  }
  TempDir dir;
  std::vector<std::filesystem::path> paths;
  BuildReport report;
};

TEST_F(BuiltModel, ReproducesEveryInputAtItsLatentPoint) {
  const Model m = Model::open(dir / "m.matlas");
  ASSERT_EQ(m.count(), 12);
  ASSERT_EQ(m.dim(), 2);
  for (int i = 0; i < m.count(); ++i) {
    const Eigen::VectorXd w = m.weights(m.latent().row(i).transpose());
    EXPECT_NEAR((w - Eigen::VectorXd::Unit(12, i)).norm(), 0.0, 1e-9);
    const BrdfTable input = read_merl(paths[static_cast<std::size_t>(i)]);
    EXPECT_LE(relative_l2(m.table(w), input, m), 1e-5) << m.names()[static_cast<std::size_t>(i)];
  }
}

TEST_F(BuiltModel, DropsColumnsMissingInAnyInputAndSaysSo) {
  EXPECT_EQ(report.dropped_columns, 1u);
  const Model m = Model::open(dir / "m.matlas");
  const std::size_t v = 1 * test::kSmallDims.bins() + 17;
  EXPECT_FALSE(m.kept(v));
  const BrdfTable t = export_table(m, m.weights(Eigen::Vector2d(0.1, 0.2)));
  EXPECT_FALSE(t.measured(1, 17));
  EXPECT_EQ(t.stored()[v], -1.0);
}

TEST_F(BuiltModel, RecordsTheHashOfEachSourcesValueBytes) {
  // Independent expectation: xxh3-64 of each file's bytes after the 12-byte header, read whole.
  const Model m = Model::open(dir / "m.matlas");
  const auto& sources = m.metadata()["sources"];
  ASSERT_EQ(sources.size(), paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    std::ifstream in(paths[i], std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    char want[17];
    std::snprintf(want, sizeof want, "%016llx",
                  static_cast<unsigned long long>(XXH3_64bits(bytes.data() + 12, bytes.size() - 12)));
    EXPECT_EQ(sources[i]["xxh3_64"].get<std::string>(), want) << paths[i];
  }
}

TEST_F(BuiltModel, ATableOfFewWeightsIsTheirWeightedSum) {
  // Two non-zero weights of twelve (convex weights are sparse): Model::table reads only those.
  const Model m = Model::open(dir / "m.matlas");
  const BrdfTable a = read_merl(paths[2]), b = read_merl(paths[7]);
  Eigen::VectorXd w = Eigen::VectorXd::Zero(m.count());
  w[2] = 0.3;
  w[7] = 0.7;
  const BrdfTable t = m.table(w);
  const std::size_t bins = t.bins();
  double worst = 0;
  for (std::size_t v = 0; v < t.size(); ++v) {
    if (!m.kept(v)) continue;
    const int c = static_cast<int>(v / bins);
    const double expected = 0.3 * a.value(c, v % bins) + 0.7 * b.value(c, v % bins);
    worst = std::max(worst, std::abs(t.value(c, v % bins) - expected) / (std::abs(expected) + 1e-3));
    ASSERT_NEAR(t.value(c, v % bins), m.value(v, w), 1e-12 * (1 + std::abs(expected)));  // the dense path
  }
  EXPECT_LT(worst, 1e-5);
}

TEST_F(BuiltModel, InterpolationIsTheExplicitWeightedSumOfInputs) {
  const Model m = Model::open(dir / "m.matlas");
  std::vector<BrdfTable> inputs;
  for (const auto& p : paths) inputs.push_back(read_merl(p));
  const Eigen::VectorXd x = 0.5 * (m.latent().row(0) + m.latent().row(5)).transpose() + Eigen::Vector2d(0.05, -0.1);
  const Eigen::VectorXd w = m.weights(x);
  const BrdfTable t = m.table(w);
  const std::size_t bins = t.bins();
  double worst = 0;
  for (std::size_t v = 0; v < t.size(); ++v) {
    if (!m.kept(v)) continue;
    const int c = static_cast<int>(v / bins);
    double mean = 0;
    for (const auto& z : inputs) mean += z.value(c, v % bins) / 12.0;
    double expected = mean;
    for (int i = 0; i < 12; ++i) expected += w[i] * (inputs[static_cast<std::size_t>(i)].value(c, v % bins) - mean);
    worst = std::max(worst, std::abs(t.value(c, v % bins) - expected) / (std::abs(expected) + 1e-3));
  }
  EXPECT_LT(worst, 1e-5);
  // Single-value queries agree with the table.
  EXPECT_NEAR(m.value(123, w), t.value(0, 123), 1e-12);
}

TEST_F(BuiltModel, AlbedoIsLinearAndMatchesDirectIntegration) {
  const Model m = Model::open(dir / "m.matlas");
  const BrdfTable input = read_merl(paths[7]);
  const auto curve = m.albedo_curve(m.material_weights(7));
  // The metadata says how the curves were integrated (docs/MODEL_FORMAT.md).
  EXPECT_NE(m.metadata().value("albedo", std::string()).find("half-vector"), std::string::npos);
  for (int t : {0, 30, 60, 89}) {
    const Rgb direct = directional_albedo(input, (t + 0.5) / 90.0 * kPi / 2);
    // The model's curve skips the one dropped column; allow for it.
    EXPECT_NEAR(curve[static_cast<std::size_t>(t)][0], direct[0], 2e-3 * direct[0] + 1e-9) << t;
  }
  const Eigen::VectorXd w = m.weights(Eigen::Vector2d(0.2, -0.3));
  const auto mixed = m.albedo_curve(w);
  Rgb expected = Rgb::Zero();
  const Eigen::MatrixXd& a = m.material_albedo();
  const Eigen::RowVectorXd mean = a.colwise().mean();
  for (int c = 0; c < 3; ++c) expected[c] = mean[c] + w.dot(a.col(c) - Eigen::VectorXd::Constant(12, mean[c]));
  EXPECT_NEAR(mixed[0][0], expected[0], 1e-12);
}

TEST_F(BuiltModel, ProjectionFindsAnInputAtItsOwnPoint) {
  const Model m = Model::open(dir / "m.matlas");
  const Projection p = project_material(m, read_merl(paths[4]));
  EXPECT_EQ(p.nearest, 4);
  EXPECT_LT(p.relative_error, 1e-4);
  EXPECT_LT((p.x - m.latent().row(4).transpose()).norm(), 1e-2);
  // A new material from the same family projects with a small residual.
  const Projection q = project_material(m, test::smooth_table(0.5, 0.5));
  EXPECT_LT(q.relative_error, q.nearest_relative_error + 1e-12);
}

TEST(NearestMaterials, AreSortedByDistanceWithTiesInIndexOrder) {
  const Eigen::VectorXd d2 = (Eigen::VectorXd(5) << 4.0, 1.0, 9.0, 1.0, 0.5).finished();
  EXPECT_EQ(nearest_materials(d2, 3), (std::vector<int>{4, 1, 3}));
  EXPECT_EQ(nearest_materials(d2, 9), (std::vector<int>{4, 1, 3, 0, 2}));  // no more than there are
  EXPECT_TRUE(nearest_materials(d2, 0).empty());
}

TEST_F(BuiltModel, ProjectionGradientMatchesFiniteDifferences) {
  const Model m = Model::open(dir / "m.matlas");
  const MaterialInnerProducts ip = inner_products(m, test::smooth_table(0.3, 0.7));
  const Eigen::Vector2d x(0.1, 0.2);
  Eigen::VectorXd g;
  projection_residual(m, ip, x, &g);
  for (int k = 0; k < 2; ++k) {
    const double h = 1e-6;
    Eigen::Vector2d a = x, b = x;
    a[k] += h;
    b[k] -= h;
    const double fd = (projection_residual(m, ip, a) - projection_residual(m, ip, b)) / (2 * h);
    EXPECT_NEAR(g[k], fd, 1e-5 * (std::abs(fd) + 1e-3));
  }
}

TEST(BuildModel, IsDeterministicAndIndependentOfBlockSize) {
  TempDir dir;
  test::write_database(dir / "db", 8);
  const MaterialSet set = MaterialSet::open({dir / "db"});
  build_model(set, small_options(), dir / "a.matlas");
  BuildOptions big = small_options();
  big.block_columns = 1 << 20;
  build_model(set, big, dir / "b.matlas");
  const Model a = Model::open(dir / "a.matlas"), b = Model::open(dir / "b.matlas");
  // Blocks change only the summation order of the Gram matrix: equal to rounding...
  EXPECT_LT((a.gram() - b.gram()).norm(), 1e-12 * a.gram().norm());
  // ...and the optimiser, stopping at a relative tolerance, lands on the same optimum (the
  // layout's Gram comes from single-precision slices, whose sums differ by about 1e-7 between
  // block sizes, so the likelihood agrees to about 1e-6 to 1e-5, not to double rounding: the
  // sanitizer build on an AMD EPYC VM (other vector kernels) read 1.7e-5, with the latent
  // distances below still within 1e-2).
  EXPECT_NEAR(a.metadata()["log_likelihood"].get<double>(), b.metadata()["log_likelihood"].get<double>(),
              1e-4 * std::abs(a.metadata()["log_likelihood"].get<double>()));
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < i; ++j)
      EXPECT_NEAR((a.latent().row(i) - a.latent().row(j)).norm(), (b.latent().row(i) - b.latent().row(j)).norm(), 1e-2);
  build_model(set, small_options(), dir / "c.matlas");
  EXPECT_EQ(a.latent(), Model::open(dir / "c.matlas").latent());
}

TEST(BuildModel, SparseLatentOptimisationWithAllPointsInducingIsTheExactOne) {
  TempDir dir;
  test::write_database(dir / "db", 10);
  const MaterialSet set = MaterialSet::open({dir / "db"});
  BuildOptions exact = small_options();
  exact.optimize.starts = 1;
  build_model(set, exact, dir / "exact.matlas");
  BuildOptions sparse = exact;
  sparse.sparse = gp::SparseOptions{10, 10};  // m = n, r = n: the exact objective
  sparse.sparse.block = 1;
  build_model(set, sparse, dir / "sparse.matlas");
  const Model a = Model::open(dir / "exact.matlas"), b = Model::open(dir / "sparse.matlas");
  EXPECT_EQ(a.metadata()["latent_optimization"]["method"], "exact");
  EXPECT_EQ(b.metadata()["latent_optimization"]["method"], "sparse");
  EXPECT_EQ(b.metadata()["latent_optimization"]["inducing"], 10);
  EXPECT_NEAR(b.metadata()["log_likelihood"].get<double>(), a.metadata()["log_likelihood"].get<double>(),
              1e-4 * std::abs(a.metadata()["log_likelihood"].get<double>()));
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < i; ++j)
      EXPECT_NEAR((a.latent().row(i) - a.latent().row(j)).norm(), (b.latent().row(i) - b.latent().row(j)).norm(), 2e-2);
  // Coarse-to-fine: 4 of the 10 placed first; the model records it and is a valid map.
  BuildOptions coarse = sparse;
  coarse.sparse.coarse = 4;
  build_model(set, coarse, dir / "coarse.matlas");
  const Model c = Model::open(dir / "coarse.matlas");
  EXPECT_EQ(c.metadata()["latent_optimization"]["coarse"], 4);
  EXPECT_EQ(c.latent().rows(), 10);
  EXPECT_TRUE(c.latent().allFinite());
  EXPECT_EQ(b.metadata()["latent_optimization"]["coarse"], 0);  // automatic: all at once below 2000
  coarse.sparse.coarse = -2;
  EXPECT_THROW(build_model(set, coarse, dir / "negative.matlas"), Error);
  // The exact placement's coarse-to-fine (--coarse): recorded likewise; refused beside the sparse one.
  EXPECT_EQ(a.metadata()["latent_optimization"]["coarse"], 0);
  BuildOptions exact_coarse = exact;
  exact_coarse.optimize.coarse = 4;
  build_model(set, exact_coarse, dir / "exact-coarse.matlas");
  const Model d = Model::open(dir / "exact-coarse.matlas");
  EXPECT_EQ(d.metadata()["latent_optimization"]["method"], "exact");
  EXPECT_EQ(d.metadata()["latent_optimization"]["coarse"], 4);
  EXPECT_TRUE(d.latent().allFinite());
  EXPECT_NE(d.latent(), a.latent());
  exact_coarse.sparse = sparse.sparse;
  EXPECT_THROW(build_model(set, exact_coarse, dir / "both.matlas"), Error);
  exact_coarse = exact;
  exact_coarse.optimize.coarse = -2;
  EXPECT_THROW(build_model(set, exact_coarse, dir / "negative-exact.matlas"), Error);
  sparse.optimize.method = gp::Optimizer::hooke_jeeves;
  EXPECT_THROW(build_model(set, sparse, dir / "hj.matlas"), Error);
}

TEST(BuildModel, ResultDoesNotDependOnFileOrderOrDataScale) {
  TempDir dir;
  auto paths = test::write_database(dir / "db", 8);
  test::write_database(dir / "scaled", 8, 1, 1000.0);
  build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "a.matlas");
  std::vector<std::filesystem::path> reversed(paths.rbegin(), paths.rend());
  build_model(MaterialSet::open(reversed), small_options(), dir / "r.matlas");
  build_model(MaterialSet::open({dir / "scaled"}), small_options(), dir / "s.matlas");
  const Model a = Model::open(dir / "a.matlas"), r = Model::open(dir / "r.matlas"),
              s = Model::open(dir / "s.matlas");
  // The same optimum (L is invariant to the order; scaling the data shifts L by a constant)...
  const double la = a.metadata()["log_likelihood"].get<double>();
  EXPECT_NEAR(r.metadata()["log_likelihood"].get<double>(), la, 1e-6 * std::abs(la));
  // ...and the same layout up to a rigid motion and the optimiser's tolerance: compare pairwise
  // distances (latent spreads are O(1)).
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const double d = (a.latent().row(i) - a.latent().row(j)).norm();
      const int ri = r.index_of(a.names()[static_cast<std::size_t>(i)]);
      const int rj = r.index_of(a.names()[static_cast<std::size_t>(j)]);
      EXPECT_NEAR((r.latent().row(ri) - r.latent().row(rj)).norm(), d, 1e-2);
      EXPECT_NEAR((s.latent().row(i) - s.latent().row(j)).norm(), d, 1e-2);
    }
}

TEST(BuildModel, RejectsBadInputsWithClearMessages) {
  TempDir dir;
  auto paths = test::write_database(dir / "db", 4);
  std::filesystem::copy_file(paths[1], dir / "db" / "copy-of-mat01.binary");
  std::ofstream(dir / "db" / "README.txt") << "copyright notice";
  const MaterialSet set = MaterialSet::open({dir / "db"});
  EXPECT_EQ(set.size(), 5u);
  EXPECT_EQ(set.ignored().size(), 1u);
  const std::string dup = error_of([&] { build_model(set, small_options(), dir / "m.matlas"); });
  EXPECT_NE(dup.find("are identical"), std::string::npos) << dup;
  EXPECT_NE(dup.find("mat01"), std::string::npos) << dup;
  EXPECT_FALSE(std::filesystem::exists(dir / "m.matlas"));

  write_merl(dir / "other.binary", test::smooth_table(0.1, 0.1, MerlDims{4, 4, 8}), true);
  const std::string mixed = error_of([&] { MaterialSet::open({paths[0], dir / "other.binary"}); });
  EXPECT_NE(mixed.find("other.binary: grid 4x4x8 differs"), std::string::npos) << mixed;
  EXPECT_NE(error_of([&] { MaterialSet::open({paths[0]}); }).find("at least 2"), std::string::npos);
  EXPECT_NE(error_of([&] { MaterialSet::open({dir / "nope"}); }).find("no such file"), std::string::npos);
  BuildOptions bad = small_options(0);
  EXPECT_NE(error_of([&] { build_model(MaterialSet::open({paths[0], paths[2]}), bad, dir / "x"); }).find("--dim"),
            std::string::npos);
}

TEST(BuildModel, AMixtureBesideABrightMaterialIsNotADuplicate) {
  // Among many materials, one with grazing spikes (analytic conductors have them) sets the linear
  // Gram's mean squared norm; a material and its mixture with 2 % of another are then closer than
  // 1e-12 of it in the linear space, but not in the layout's: the build must place them, and still
  // refuse a true copy.
  TempDir dir;
  const auto paths = test::write_database(dir / "db", 4);
  BrdfTable bright = test::smooth_table(0.9, 0.5);
  for (int c = 0; c < 3; ++c) bright.stored()[static_cast<std::size_t>(c) * bright.bins() + bright.bins() - 1] = 1e11;
  write_merl(dir / "db" / "bright.binary", bright, /*allow_nonstandard_dims=*/true);
  const BrdfTable a = read_merl(paths[1]), b = read_merl(paths[2]);
  BrdfTable mix = a;
  for (std::size_t v = 0; v < mix.stored().size(); ++v) mix.stored()[v] = 0.98 * a.stored()[v] + 0.02 * b.stored()[v];
  write_merl(dir / "db" / "mix.binary", mix, /*allow_nonstandard_dims=*/true);
  // The premise: in the linear space the pair is within 1e-12 of the mean centred squared norm
  // (every value is measured, so every column is kept).
  std::vector<BrdfTable> all;
  for (const char* name : {"mat00", "mat01", "mat02", "mat03", "bright", "mix"})
    all.push_back(read_merl(dir / "db" / (std::string(name) + ".binary")));
  double d2 = 0, norms = 0;
  for (std::size_t v = 0; v < mix.stored().size(); ++v) {
    double mean = 0;
    for (const BrdfTable& t : all) mean += t.stored()[v] / 6.0;
    for (const BrdfTable& t : all) norms += std::pow(t.stored()[v] - mean, 2) / 6.0;
    d2 += std::pow(mix.stored()[v] - a.stored()[v], 2);
  }
  EXPECT_GT(d2, 0.0);
  EXPECT_LT(d2, 1e-12 * norms);
  build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "m.matlas");
  EXPECT_EQ(Model::open(dir / "m.matlas").count(), 6);
  std::filesystem::copy_file(dir / "db" / "mix.binary", dir / "db" / "mix-copy.binary");
  const std::string dup = error_of([&] { build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "n.matlas"); });
  EXPECT_NE(dup.find("'mix-copy' and 'mix' are identical"), std::string::npos) << dup;
}

TEST(BuildModel, CorruptedOrForeignModelsAreRejected) {
  TempDir dir;
  test::write_database(dir / "db", 5);
  build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "m.matlas");
  const auto size = std::filesystem::file_size(dir / "m.matlas");
  std::filesystem::copy_file(dir / "m.matlas", dir / "t.matlas");
  std::filesystem::resize_file(dir / "t.matlas", size - 10);
  EXPECT_NE(error_of([&] { Model::open(dir / "t.matlas"); }).find("truncated"), std::string::npos);
  // Flip one byte in the latent tensor: the checksum catches it.
  std::filesystem::copy_file(dir / "m.matlas", dir / "c.matlas");
  {
    std::fstream f(dir / "c.matlas", std::ios::in | std::ios::out | std::ios::binary);
    std::uint64_t header = 0;
    f.read(reinterpret_cast<char*>(&header), 8);
    f.seekp(static_cast<std::streamoff>(8 + header + 3));
    f.put('\x55');
  }
  EXPECT_NE(error_of([&] { Model::open(dir / "c.matlas"); }).find("checksum"), std::string::npos);
  // A MERL file is not a model.
  EXPECT_NE(error_of([&] { Model::open(dir / "db" / "mat00.binary"); }).find("not a"), std::string::npos);
}

TEST(BuildModel, Float16StorageStaysAccurate) {
  TempDir dir;
  auto paths = test::write_database(dir / "db", 6);
  BuildOptions o = small_options();
  o.storage = Storage::f16;
  const BuildReport r = build_model(MaterialSet::open({dir / "db"}), o, dir / "h.matlas");
  EXPECT_GT(r.storage_relative_error, 1e-5);  // really rounded to half precision
  EXPECT_LT(r.storage_relative_error, 1e-3);
  const Model m = Model::open(dir / "h.matlas");
  EXPECT_EQ(m.storage(), "F16");
  EXPECT_LE(relative_l2(m.table(m.material_weights(2)), read_merl(paths[2]), m), 1e-3);
}

TEST(BuildModel, Float16ModelWithAnOddDataSizeOpens) {
  // 7 materials and an odd number of kept columns: 2-byte data of odd length leaves the mean
  // that follows it unaligned in the map, which the reader must handle.
  TempDir dir;
  auto paths = test::write_database(dir / "db", 7);
  BrdfTable with_gap = read_merl(paths[0]);
  with_gap.stored()[17] = -1.0;  // one value not measured: its column is dropped
  write_merl(paths[0], with_gap, /*allow_nonstandard_dims=*/true);
  BuildOptions o = small_options();
  o.storage = Storage::f16;
  const BuildReport r = build_model(MaterialSet::open({dir / "db"}), o, dir / "h.matlas");
  ASSERT_EQ(r.kept_columns % 2, 1u) << "the test needs an odd number of kept columns";
  const Model m = Model::open(dir / "h.matlas");
  EXPECT_LE(relative_l2(m.table(m.material_weights(4)), read_merl(paths[4]), m), 1e-3);
}

TEST(BuildModel, ExportClampsNegativeValues) {
  TempDir dir;
  test::write_database(dir / "db", 6);
  build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "m.matlas");
  const Model m = Model::open(dir / "m.matlas");
  // Extrapolating weights produce negative values somewhere.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(6);
  w[0] = 4.0;
  w[1] = -3.0;
  ExportStats stats;
  const BrdfTable t = export_table(m, w, &stats);
  EXPECT_GT(stats.clamped, 0u);
  EXPECT_LT(stats.most_negative, 0.0);
  for (double v : t.stored()) EXPECT_GE(v, 0.0);
}

}  // namespace
}  // namespace matlas

namespace matlas {
namespace {

TEST(BuildModel, DarkMaterialsBesideABrightOneAreReproducedAndProjectedExactly) {
  // A mirror-like table 10^4 times brighter than the others dominates the mean: storing the
  // inputs (not the centred data) keeps the dark ones exact at their own points.
  test::TempDir dir;
  auto paths = test::write_database(dir / "db", 5);
  BrdfTable bright = test::smooth_table(0.9, 0.1);
  for (double& v : bright.stored()) v *= 1e4;
  write_merl(dir / "db" / "zz-bright.binary", bright, true);
  build_model(MaterialSet::open({dir / "db"}), small_options(), dir / "m.matlas");
  const Model m = Model::open(dir / "m.matlas");
  for (int i = 0; i < 5; ++i) {
    const BrdfTable input = read_merl(paths[static_cast<std::size_t>(i)]);
    EXPECT_LE(relative_l2(m.table(m.weights(m.latent().row(i).transpose())), input, m), 1e-6);
    const Projection p = project_material(m, input);
    EXPECT_EQ(p.nearest, i);
    EXPECT_LT(p.relative_error, 1e-6);
  }
}

}  // namespace
}  // namespace matlas
