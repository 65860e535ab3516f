// The RGL measured BSDF: the warp, evaluation against closed forms on synthetic files, and the
// six real materials of ../shared/data/rgl (resampling, reciprocity, albedo).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <random>

#include <gtest/gtest.h>

#include "brdf/albedo.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/parallel.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"
#include "rgl_test_files.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

namespace fs = std::filesystem;

using test::error_of;

RglBsdf synthetic(const test::SyntheticRgl& s = {}) {
  return RglBsdf(TensorFile::parse(serialize_tensor_file(s.fields()), "synthetic.bsdf"));
}

Vec3 random_direction(std::mt19937& rng, double min_z = 0.02) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (;;) {
    const double z = u(rng), phi = 2 * kPi * u(rng), r = std::sqrt(std::max(0.0, 1 - z * z));
    if (z >= min_z) return {r * std::cos(phi), r * std::sin(phi), z};
  }
}

// ---- the warp

TEST(RglWarp, InvertUndoesSampleWithBlendedSlices) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.05, 2.0);
  const std::size_t nx = 7, ny = 5, slices = 4;
  std::vector<float> data(nx * ny * slices);
  for (auto& v : data) v = static_cast<float>(u(rng));
  const RglWarp2D warp(data, nx, ny, slices, true);
  const std::vector<float> outer{0.0f, 1.0f}, inner{0.0f, 2.0f};
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const double y = 2 * unit(rng);  // sequenced: argument order is unspecified
    const double x = unit(rng);
    const ParamBlend b = blend_params(outer, x, inner, y);
    const double a = unit(rng), c = unit(rng);
    const auto p = warp.sample(a, c, b);
    const auto q = warp.invert(p[0], p[1], b);
    EXPECT_NEAR(q[0], a, 1e-9);
    EXPECT_NEAR(q[1], c, 1e-9);
  }
}

TEST(RglWarp, InvertIsTheMarginalAndConditionalCdf) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.1, 3.0);
  const std::size_t nx = 4, ny = 6;
  std::vector<float> data(nx * ny);
  for (auto& v : data) v = static_cast<float>(u(rng));
  const RglWarp2D warp(data, nx, ny, 1, true);
  const ParamBlend none;
  // The density integrates to 1; the marginal CDF of y and the conditional CDF of x by midpoint
  // quadrature of eval().
  const int n = 600;
  double total = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) total += warp.eval((i + 0.5) / n, (j + 0.5) / n, none);
  EXPECT_NEAR(total / (n * n), 1.0, 1e-5);
  const double x = 0.37, y = 0.61;
  double below = 0, row_below = 0, row = 0;
  for (int j = 0; j < n; ++j) {
    const double yy = y * (j + 0.5) / n;
    for (int i = 0; i < n; ++i) below += warp.eval((i + 0.5) / n, yy, none) * y / (n * n);
  }
  for (int i = 0; i < 4 * n; ++i) {
    const double xx = (i + 0.5) / (4 * n);
    row += warp.eval(xx, y, none);
    if (xx < x) row_below += warp.eval(xx, y, none);
  }
  const auto inv = warp.invert(x, y, none);
  EXPECT_NEAR(inv[1], below, 1e-4);
  EXPECT_NEAR(inv[0], row_below / row, 2e-3);
}

TEST(RglWarp, UniformDataInvertsToTheIdentity) {
  const std::vector<float> data(5 * 3, 2.0f);
  const RglWarp2D warp(data, 5, 3, 1, true);
  for (double x : {0.0, 0.13, 0.5, 0.99, 1.0})
    for (double y : {0.0, 0.3, 1.0}) {
      const auto p = warp.invert(x, y, ParamBlend{});
      EXPECT_NEAR(p[0], x, 1e-12);
      EXPECT_NEAR(p[1], y, 1e-12);
    }
}

TEST(RglWarp, ParamIntervalClampsAndInterpolates) {
  const std::vector<float> v{0.0f, 1.0f, 3.0f};
  EXPECT_EQ(param_interval(v, -1.0), (std::pair<std::size_t, double>{0, 0.0}));
  EXPECT_EQ(param_interval(v, 0.5), (std::pair<std::size_t, double>{0, 0.5}));
  EXPECT_EQ(param_interval(v, 2.0), (std::pair<std::size_t, double>{1, 0.5}));
  EXPECT_EQ(param_interval(v, 3.0), (std::pair<std::size_t, double>{1, 1.0}));
  EXPECT_EQ(param_interval(v, 9.0), (std::pair<std::size_t, double>{1, 1.0}));
  const std::vector<float> one{0.7f};
  EXPECT_EQ(param_interval(one, 5.0), (std::pair<std::size_t, double>{0, 0.0}));
  const ParamBlend b = blend_params({}, 0.0, v, 2.0);
  ASSERT_EQ(b.count, 2);
  EXPECT_EQ(b.slice[0], 1u);
  EXPECT_EQ(b.slice[1], 2u);
  EXPECT_DOUBLE_EQ(b.weight[0] + b.weight[1], 1.0);
}

// ---- evaluation of synthetic files

/// The closed form of test::SyntheticRgl, from the definitions (unit coordinates of the half
/// vector relative to phi_i, D / (4 sigma)), independently of the implementation.
Rgb expected_synthetic(const Vec3& wi, const Vec3& wo, bool jacobian = true) {
  const Vec3 m = (wi + wo).normalized();
  const double theta_i = std::acos(wi.z()), theta_m = std::acos(std::min(1.0, m.z()));
  const double phi_i = std::atan2(wi.y(), wi.x()), phi_m = std::atan2(m.y(), m.x());
  const double x = std::sqrt(theta_m / (kPi / 2));
  double y = (phi_m - phi_i + kPi) / (2 * kPi);
  y -= std::floor(y);
  const double xi = std::sqrt(theta_i / (kPi / 2));
  Rgb r;
  for (int c = 0; c < 3; ++c) r[c] = test::SyntheticRgl::reflectance(c, theta_i, x, y);
  if (jacobian) r *= (1.0 + x) / (4.0 * (0.5 + 0.25 * xi));
  return r;
}

TEST(RglBsdf, SyntheticEvaluationMatchesTheClosedForm) {
  const RglBsdf b = synthetic();
  EXPECT_TRUE(b.isotropic());
  EXPECT_FALSE(b.spectral());
  EXPECT_EQ(b.description(), "synthetic test material");
  EXPECT_EQ(b.summary(), "isotropic, RGB, 4 x 1 incident directions, VNDF 6x6, reflectance 5x5");
  std::mt19937 rng(11);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec3 wi = random_direction(rng), wo = random_direction(rng);
    const Rgb got = b.eval_cosine(wi, wo), want = expected_synthetic(wi, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1e-5 * want[c]) << trial;
    EXPECT_NEAR(b.eval(wi, wo)[1], want[1] / wo.z(), 1e-5 * want[1] / wo.z());
  }
  // Directions are normalised; NaN directions read as 0.
  const Vec3 wi(0.3, 0.2, 0.9), wo(-0.4, 0.1, 0.7);
  EXPECT_NEAR(b.eval(2.0 * wi, 3.0 * wo)[1], b.eval(wi.normalized(), wo.normalized())[1], 1e-12);
  EXPECT_EQ(b.eval_cosine(Vec3(std::nan(""), 0, 1), Vec3(0, 0, 1)).sum(), 0.0);
  // Below the horizon: zero.
  EXPECT_EQ(b.eval_cosine(Vec3(0, 0, -1), Vec3(0, 0, 1)).sum(), 0.0);
  EXPECT_EQ(b.eval_cosine(Vec3(0, 0, 1), Vec3(1, 0, 0)).sum(), 0.0);
}

TEST(RglBsdf, NegativeReflectanceIsClippedAtZeroAsRglsLoaderDoes) {
  // Saturated colours leave negative samples in real files (iris_purple_gem: 18 % of its values
  // at random directions); RGL's loader, and so Mitsuba, clips them, and so does the evaluation.
  test::SyntheticRgl s;
  s.scale = -1.0;  // every sample negative
  const RglBsdf negative = synthetic(s);
  EXPECT_EQ(negative.negative_samples(), negative.reflectance_samples());
  EXPECT_EQ(synthetic().negative_samples(), 0u);
  std::mt19937 rng(13);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 wi = random_direction(rng), wo = random_direction(rng);
    EXPECT_EQ(negative.eval_cosine(wi, wo).maxCoeff(), 0.0) << trial;
    EXPECT_EQ(negative.eval_cosine(wi, wo).minCoeff(), 0.0) << trial;
  }
}

TEST(RglBsdf, WithoutJacobianTheTableIsTheValue) {
  test::SyntheticRgl s;
  s.jacobian = false;
  const RglBsdf b = synthetic(s);
  std::mt19937 rng(12);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 wi = random_direction(rng), wo = random_direction(rng);
    EXPECT_NEAR(b.eval_cosine(wi, wo)[2], expected_synthetic(wi, wo, false)[2], 1e-5);
  }
}

TEST(RglBsdf, AFlatSpectrumIsWhite) {
  test::SyntheticRgl s;
  for (int l = 360; l <= 830; l += 10) s.wavelengths.push_back(static_cast<float>(l));
  const RglBsdf b = synthetic(s);
  EXPECT_TRUE(b.spectral());
  EXPECT_EQ(b.wavelength_count(), 48u);
  std::mt19937 rng(13);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 wi = random_direction(rng), wo = random_direction(rng);
    const Rgb got = b.eval_cosine(wi, wo);
    const double want = expected_synthetic(wi, wo)[1];  // every wavelength holds channel 1's formula
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want, 1e-4 * want);
  }
}

TEST(RglBsdf, ResamplingFollowsTheMerlGrid) {
  const RglBsdf b = synthetic();
  RglResampling r;
  const MerlDims dims{16, 8, 12};
  const BrdfTable t = resample_to_merl(b, &r, dims);
  EXPECT_EQ(r.bins, dims.bins());
  EXPECT_EQ(r.measured_bins + r.missing_bins, r.bins);
  EXPECT_EQ(r.clamped_values, 0u);
  std::size_t missing = 0, averaged = 0, off_centre = 0;
  for (int i = 0; i < dims.theta_h; ++i)
    for (int j = 0; j < dims.theta_d; ++j)
      for (int k = 0; k < dims.phi_d; ++k) {
        const std::size_t bin = dims.flat(i, j, k);
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        if (d.wi.z() <= 0 || d.wo.z() <= 0) {
          ++missing;
          for (int c = 0; c < 3; ++c) EXPECT_FALSE(t.measured(c, bin));
          continue;
        }
        const Rgb want = b.eval_reciprocal(d.wi, d.wo);
        const double theta_h_end = std::pow((i + 1.0) / dims.theta_h, 2) * kPi / 2;
        if (theta_h_end > 0.2) {  // the value at the bin centre
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.value(c, bin), want[c], 1e-12 * (1 + want[c]));
          continue;
        }
        // Near the mirror direction, the average over the bin: within the range of the model's
        // values over the bin (a 9 x 9 grid with its edges).
        ++averaged;
        Rgb lo = Rgb::Constant(1e300), hi = Rgb::Constant(-1e300);
        for (int s = 0; s <= 8; ++s)
          for (int u = 0; u <= 8; ++u) {
            HalfDiffAngles a = bin_centre(dims, i, j, k);
            a.theta_h = std::pow((i + s / 8.0) / dims.theta_h, 2) * kPi / 2;
            a.theta_d = (j + u / 8.0) / dims.theta_d * kPi / 2;
            const DirectionPair e = from_half_diff(a);
            if (e.wi.z() <= 0 || e.wo.z() <= 0) continue;
            const Rgb v = b.eval_reciprocal(e.wi, e.wo);
            lo = lo.min(v);
            hi = hi.max(v);
          }
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(t.value(c, bin), lo[c] - 1e-9 * (1 + hi[c]));
          EXPECT_LE(t.value(c, bin), hi[c] + 1e-9 * (1 + hi[c]));
        }
        if (std::abs(t.value(0, bin) - want[0]) > 1e-6 * want[0]) ++off_centre;
      }
  EXPECT_GT(averaged, 0u);
  EXPECT_GT(off_centre, averaged / 2);  // averages, not the centre values
  EXPECT_EQ(missing, r.missing_bins);
  EXPECT_GT(r.reciprocity_error, 0.0);  // the synthetic model is not reciprocal
}

TEST(RglBsdf, ReciprocalEvaluationIsSymmetric) {
  const RglBsdf b = synthetic();
  std::mt19937 rng(14);
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 wi = random_direction(rng), wo = random_direction(rng);
    const Rgb a = b.eval_reciprocal(wi, wo), c = b.eval_reciprocal(wo, wi);
    EXPECT_NEAR(a[0], c[0], 1e-12 * a[0]);
    // With equal cosines it is the plain average of the two orders.
  }
  const Vec3 wi = Vec3(0.6, 0.0, 0.8), wo = Vec3(-0.48, 0.36, 0.8);
  const Rgb avg = 0.5 * (b.eval(wi, wo) + b.eval(wo, wi));
  EXPECT_NEAR(b.eval_reciprocal(wi, wo)[1], avg[1], 1e-12);
}

TEST(RglBsdf, AnisotropicMaterialsAreEvaluatedButNotResampled) {
  test::SyntheticRgl s;
  s.phi_i = {-3.1415927f, -2.3561945f, -1.5707964f};  // a quarter: 4-fold symmetry
  const RglBsdf b = synthetic(s);
  EXPECT_FALSE(b.isotropic());
  std::mt19937 rng(15);
  const Vec3 wi = random_direction(rng), wo = random_direction(rng);
  EXPECT_TRUE(b.eval_cosine(wi, wo).allFinite());
  // The reduction folds mirror-symmetric directions together.
  const Vec3 mi(-wi.x(), wi.y(), wi.z()), mo(-wo.x(), wo.y(), wo.z());
  EXPECT_NEAR(b.eval_cosine(wi, wo)[0], b.eval_cosine(mi, mo)[0], 1e-12);
  const std::string e = error_of([&] { resample_to_merl(b); });
  EXPECT_NE(e.find("synthetic.bsdf: anisotropic"), std::string::npos) << e;
  EXPECT_NE(e.find("not supported yet"), std::string::npos) << e;
}

TEST(RglBsdf, InvalidFieldsAreRejectedNamingTheFileAndField) {
  auto expect_error = [](std::vector<TensorField> fields, const std::string& want) {
    const std::string e = error_of([&] { RglBsdf(TensorFile::parse(serialize_tensor_file(fields), "bad.bsdf")); });
    EXPECT_EQ(e.rfind("bad.bsdf: ", 0), 0u) << e;
    EXPECT_NE(e.find(want), std::string::npos) << e;
  };
  const auto good = test::SyntheticRgl{}.fields();
  auto without = [&](const std::string& name) {
    std::vector<TensorField> f;
    for (const auto& x : good)
      if (x.name != name) f.push_back(x);
    return f;
  };
  auto with = [&](const std::string& name, const std::function<void(TensorField&)>& edit) {
    auto f = good;
    for (auto& x : f)
      if (x.name == name) edit(x);
    return f;
  };
  expect_error(without("vndf"), "no field 'vndf'");
  expect_error(without("rgb"), "no field 'rgb'");
  expect_error(without("jacobian"), "no field 'jacobian'");
  expect_error(with("vndf",
                    [](TensorField& f) {
                      f.shape = {1, 2, 6, 18};
                      f.data.resize(f.count() * 4);  // else the header claims bytes of the next field
                    }),
               "field 'vndf' is float32 [1, 2, 6, 18]");
  expect_error(with("theta_i", [](TensorField& f) { f.dtype = TensorType::Int32; }), "field 'theta_i' is int32");
  expect_error(with("rgb", [](TensorField& f) {
                 const float nan = std::nanf("");
                 std::memcpy(f.data.data() + 40, &nan, 4);
               }),
               "NaN value in field 'rgb' at element 10");
  expect_error(with("sigma", [](TensorField& f) { std::memset(f.data.data(), 0, 4); }), "'sigma'");
  expect_error(with("vndf", [](TensorField& f) { std::memset(f.data.data(), 0, f.data.size()); }), "'vndf' is zero");
  expect_error(with("theta_i", [](TensorField& f) { std::memset(f.data.data() + 4, 0, 4); }), "not strictly increasing");
}

TEST(RglBsdf, ResamplingRefusesValuesNoMerlFileMayHold) {
  // Finite float32 values near 1e30 passed every check, and resample_to_merl then produced
  // tables that write_merl wrote and every MERL reader (ours too) refuses.
  test::SyntheticRgl s;
  s.scale = 1e30;
  const MerlDims dims{9, 9, 18};  // a small grid: the same code, a hundredth of the bins
  const std::string e = error_of([&] { resample_to_merl(synthetic(s), nullptr, dims); });
  EXPECT_EQ(e.rfind("synthetic.bsdf: resampled onto the MERL grid, the material's value at bin ", 0), 0u) << e;
  EXPECT_NE(e.find("beyond what MERL files hold (1e15 in stored units)"), std::string::npos) << e;
  // A merely bright material is fine.
  s.scale = 1e6;
  EXPECT_NO_THROW(resample_to_merl(synthetic(s), nullptr, dims));
}

TEST(RglBsdf, OwnedFilesGiveTheSameMaterial) {
  // RglBsdf(TensorFile&&) frees each field once converted: the same material as from a const
  // file, whose fields are left as they were.
  for (const bool spectral : {false, true}) {
    test::SyntheticRgl s;
    if (spectral) s.wavelengths = {400, 500, 600, 700};
    const TensorFile file = TensorFile::parse(serialize_tensor_file(s.fields()), "s.bsdf");
    const RglBsdf kept(file);
    TensorFile copy = file;
    const RglBsdf owned(std::move(copy));
    for (const auto& f : file.fields()) EXPECT_EQ(f.data.size(), f.count() * tensor_type_size(f.dtype)) << f.name;
    std::mt19937 rng(5);
    for (int i = 0; i < 200; ++i) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      EXPECT_TRUE((kept.eval(wi, wo) == owned.eval(wi, wo)).all());
    }
    EXPECT_EQ(kept.summary(), owned.summary());
  }
}

TEST(RglBsdf, ReadBrdfDispatchesOnTheExtension) {
  test::TempDir dir;
  write_tensor_file(dir / "s.bsdf", test::SyntheticRgl{}.fields());
  const BrdfTable t = read_brdf(dir / "s.bsdf");
  EXPECT_TRUE(t.dims().is_standard());
  write_merl(dir / "s.binary", t);
  const BrdfTable u = read_brdf(dir / "s.binary");
  EXPECT_EQ(0, std::memcmp(t.stored().data(), u.stored().data(), t.size() * 8));
  // A MERL file renamed .bsdf is not a tensor file.
  fs::copy_file(dir / "s.binary", dir / "m.bsdf");
  EXPECT_NE(error_of([&] { read_brdf(dir / "m.bsdf"); }).find("m.bsdf: not a tensor file"), std::string::npos);
}

// ---- the real materials of ../shared/data/rgl

class RealRgl : public ::testing::Test {
protected:
  void SetUp() override {
    dir_ = test::shared_rgl_dir();
    if (dir_.empty())
      GTEST_SKIP() << "../shared/data/rgl is not beside the source tree (set MATLAS_SHARED_DIR to the "
                      "shared folder to run the tests on the six real RGL materials)";
  }
  struct Loaded {
    std::unique_ptr<RglBsdf> bsdf;
    BrdfTable table;
    RglResampling report;
  };
  /// Each material read and resampled once for the whole suite.
  const Loaded& load(const std::string& name) {
    static std::mutex mutex;
    static std::map<std::string, Loaded> cache;
    std::lock_guard lock(mutex);
    auto it = cache.find(name);
    if (it == cache.end()) {
      Loaded l;
      l.bsdf = std::make_unique<RglBsdf>(RglBsdf::read(dir_ / (name + ".bsdf")));
      l.table = resample_to_merl(*l.bsdf, &l.report);
      it = cache.emplace(name, std::move(l)).first;
    }
    return it->second;
  }
  fs::path dir_;
};

TEST_F(RealRgl, FilesParseAsIsotropicRgb) {
  for (const auto& name : test::shared_rgl_names()) {
    const RglBsdf& b = *load(name).bsdf;
    EXPECT_TRUE(b.isotropic()) << name;
    EXPECT_FALSE(b.spectral()) << name;
    EXPECT_TRUE(b.jacobian()) << name;
    EXPECT_EQ(b.theta_i_count(), 8u) << name;
    EXPECT_FALSE(b.description().empty()) << name;
    std::printf("  %-24s %s: %s\n", name.c_str(), b.description().c_str(), b.summary().c_str());
  }
}

TEST_F(RealRgl, ResampledTablesAreReciprocalAndMarkTheHorizon) {
  std::mt19937 rng(21);
  for (const auto& name : test::shared_rgl_names()) {
    const Loaded& l = load(name);
    const BrdfTable& t = l.table;
    // 361,784 of the 1,458,000 bins have a direction below the horizon, as in MERL files.
    EXPECT_EQ(l.report.missing_bins, 361784u) << name;
    EXPECT_EQ(t.missing_count(), 3u * 361784u) << name;
    for (int trial = 0; trial < 2000; ++trial) {
      const Vec3 wi = random_direction(rng), wo = random_direction(rng);
      const Rgb a = t.lookup_smooth(wi, wo), b = t.lookup_smooth(wo, wi);
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(a[c], b[c], 1e-9 * (1 + a[c])) << name;
      ASSERT_EQ(t.lookup(wi, wo)[1], t.lookup(wo, wi)[1]) << name;
    }
    std::printf("  %-24s non-reciprocity of the measurement %5.1f %%, negative samples in the file %zu of %zu, max %.0f\n",
                name.c_str(), 100 * l.report.reciprocity_error, l.bsdf->negative_samples(), l.bsdf->reflectance_samples(),
                l.report.max_value.maxCoeff());
    // The evaluation clips at 0, so no reciprocal value is negative any more.
    EXPECT_EQ(l.report.clamped_values, 0u) << name;
  }
  // The diffuse paper is nearly reciprocal as measured: the table represents both orders of it.
  EXPECT_LT(load("paper_white_rgb").report.reciprocity_error, 0.05);
}

/// View angles of the albedo checks (degrees).
const std::vector<double> kAlbedoAngles{5, 20, 40, 60, 75};

TEST_F(RealRgl, AlbedoOfTheTableMatchesTheModelWithinOnePercent) {
  // a(wo) of the resampled table (nearest-bin lookup) against the model integrated directly
  // (its reciprocal form, negative values clamped, as stored), both by the half-vector quadrature.
  std::printf("  %-24s %5s %26s %26s %8s\n", "material", "view", "model RGB albedo", "table RGB albedo", "max rel");
  for (const auto& name : test::shared_rgl_names()) {
    const Loaded& l = load(name);
    std::vector<Rgb> model(kAlbedoAngles.size()), table(kAlbedoAngles.size());
    parallel_for_each(0, kAlbedoAngles.size(), [&](std::size_t a) {
      const Vec3 wo = direction_at_theta(kAlbedoAngles[a] * kPi / 180);
      model[a] = half_vector_albedo(
          [&](const Vec3& wi, const Vec3& v) -> Rgb { return l.bsdf->eval_reciprocal(wi, v).max(0.0); }, wo);
      // The default resolution (540 = 6 x 90) puts six points in each theta_h bin of the table.
      table[a] = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return l.table.lookup(wi, v); }, wo);
    });
    // chm_mint's specular peak (f ~ 520 / sr at normal incidence, under 0.3 degrees wide) is
    // narrower than the grid's bins there: sampled at bin centres it gained up to 1.6 %; the
    // resampling averages those bins over their theta_h extent.
    const double tolerance = 0.01;
    for (std::size_t a = 0; a < kAlbedoAngles.size(); ++a) {
      const Rgb rel = (table[a] - model[a]).abs() / model[a].max(0.01);
      std::printf("  %-24s %4.0f° %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f %7.2f%%\n", name.c_str(), kAlbedoAngles[a],
                  model[a][0], model[a][1], model[a][2], table[a][0], table[a][1], table[a][2], 100 * rel.maxCoeff());
      EXPECT_LT(rel.maxCoeff(), tolerance) << name << " at " << kAlbedoAngles[a] << " degrees";
    }
  }
}

TEST_F(RealRgl, AlbedoAgainstTheNeuralFitsOfTheSameMeasurements) {
  const char* fits = std::getenv("MATLAS_RGL_FITS_DIR");
  if (!fits)
    GTEST_SKIP() << "set MATLAS_RGL_FITS_DIR to a folder of MERL tables of the neural fits, made with "
                    "../shared/tools/nbrdf2merl.py DIR ../shared/data/nbrdf-rgl/*.h5";
  std::printf("  %-24s %s\n", "material", "luminance albedo, table vs fit, at 5 20 40 60 75 degrees");
  for (const auto& name : test::shared_rgl_names()) {
    const fs::path path = fs::path(fits) / (name + ".binary");
    if (!fs::exists(path)) GTEST_SKIP() << path << " is missing";
    const BrdfTable fit = read_merl(path);
    const Loaded& l = load(name);
    double worst = 0;
    std::string line;
    for (double angle : kAlbedoAngles) {
      const Vec3 wo = direction_at_theta(angle * kPi / 180);
      const Rgb a = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return l.table.lookup(wi, v); }, wo, 270);
      const Rgb b = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return fit.lookup(wi, v); }, wo, 270);
      const double ya = 0.2126 * a[0] + 0.7152 * a[1] + 0.0722 * a[2], yb = 0.2126 * b[0] + 0.7152 * b[1] + 0.0722 * b[2];
      const double rel = (ya - yb) / yb;
      worst = std::max(worst, std::abs(rel));
      char buf[64];
      std::snprintf(buf, sizeof buf, " %.3f/%.3f (%+.1f%%)", ya, yb, 100 * rel);
      line += buf;
    }
    std::printf("  %-24s%s\n", name.c_str(), line.c_str());
    // The fits are approximations of the same data; agreement within their own error, which
    // reaches about 15 % for the sharpest peaks: a check of units and conventions.
    EXPECT_LT(worst, 0.25) << name;
  }
}

TEST_F(RealRgl, TruncatedAndCorruptedCopiesAreRejected) {
  test::TempDir dir;
  const fs::path source = dir_ / "paper_white_rgb.bsdf";
  const std::string bytes = read_file(source);
  for (std::size_t keep : {std::size_t{0}, std::size_t{7}, std::size_t{100}, std::size_t{600000}, bytes.size() - 1}) {
    const fs::path cut = dir / ("cut" + std::to_string(keep) + ".bsdf");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(keep));
    const std::string e = error_of([&] { RglBsdf::read(cut); });
    EXPECT_EQ(e.rfind(cut.string() + ": ", 0), 0u) << e;
    EXPECT_TRUE(e.find("truncated") != std::string::npos || e.find("empty") != std::string::npos ||
                e.find("not a tensor file") != std::string::npos)
        << e;
  }
  // A value overwritten with NaN inside the reflectance table.
  std::string corrupt = bytes;
  const TensorFile f = TensorFile::parse(std::as_bytes(std::span(bytes.data(), bytes.size())), source);
  ASSERT_NE(f.find("rgb"), nullptr);
  const std::size_t offset = bytes.size() - 1024 - 8 - 3 * 8 * 32 * 32 * 4 + 4 * 100;  // rgb precedes jacobian, valid
  const float nan = std::nanf("");
  std::memcpy(corrupt.data() + offset, &nan, 4);
  const fs::path bad = dir / "nan.bsdf";
  std::ofstream(bad, std::ios::binary).write(corrupt.data(), static_cast<std::streamsize>(corrupt.size()));
  const std::string e = error_of([&] { RglBsdf::read(bad); });
  EXPECT_EQ(e.rfind(bad.string() + ": ", 0), 0u) << e;
  EXPECT_NE(e.find("NaN value in field"), std::string::npos) << e;
}

}  // namespace
}  // namespace matlas
