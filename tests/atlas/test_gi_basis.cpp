// GI bases: the composed I1 of any weights equals a direct I1 render of the model's table at
// those weights with the same random numbers (to float rounding); the full composition is exact
// at the inputs; files round-trip; the per-material cache resumes a build.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "atlas/gi_basis.h"
#include "atlas/model_material.h"
#include "brdf/catalog.h"
#include "core/error.h"
#include "formats/merl_file.h"
#include "formats/safetensors.h"
#include "formats/synth_database.h"
#include "manifold/build.h"
#include "manifold/material_set.h"
#include "support/temp_dir.h"

namespace matlas::atlas {
namespace {

using pathtrace::load_scene;
using pathtrace::trace;
using pathtrace::TraceImages;
using pathtrace::TraceSettings;
using pathtrace::World;

/// A model of six synthetic materials on a coarse grid (q = 2), built in `dir`.
Model small_model(const std::filesystem::path& dir) {
  BuildOptions options;
  options.dim = 2;
  write_database(dir / "db", random_catalog(6, 11), null_progress(), MerlDims{16, 16, 32});
  build_model(MaterialSet::open({dir / "db"}), options, dir / "m.matlas");
  return Model::open(dir / "m.matlas");
}

class GiBasisTest : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir("matlas-gi");
    model_ = new Model(small_model(dir_->path()));
    world_ = new World(load_scene("box", "sphere"));
  }
  static void TearDownTestSuite() {
    delete world_;
    delete model_;
    delete dir_;
  }
  static TraceSettings settings() {
    TraceSettings s;
    s.width = 20;
    s.height = 16;
    s.spp = 4;
    s.seed = 7;
    return s;
  }
  /// Direct render of the model's table at weights w, with the basis's random numbers.
  /// (Model::bin_rgb: the same values as Model::table(w), negative ones of an extrapolation kept.)
  static TraceImages direct(const Eigen::VectorXd& w) {
    return trace(*world_, model_point_bank(*model_, w).get(), settings());
  }
  /// Largest difference over the reference's largest magnitude.
  static double max_relative(const Image& a, const Image& b) {
    const Eigen::Map<const Eigen::ArrayXf> x(a.rgb.data(), static_cast<Eigen::Index>(a.rgb.size()));
    const Eigen::Map<const Eigen::ArrayXf> y(b.rgb.data(), static_cast<Eigen::Index>(b.rgb.size()));
    return static_cast<double>((x - y).abs().maxCoeff() / y.abs().maxCoeff());
  }
  static inline test::TempDir* dir_ = nullptr;
  static inline Model* model_ = nullptr;
  static inline World* world_ = nullptr;
};

TEST_F(GiBasisTest, ComposedI1EqualsTheDirectRenderOfTheInterpolatedTable) {
  const GiBasis basis = build_gi_basis(*model_, *world_, settings(), {});
  ASSERT_EQ(basis.count(), model_->count());
  Eigen::VectorXd x = model_->latent().colwise().mean().transpose();
  // An interpolation (convex weights at the latent centroid) and an extrapolation (a negative
  // weight, weights summing to 2.5: an unphysical table, but the image must stay linear).
  const std::vector<Eigen::VectorXd> weights = {model_->weights(x), Eigen::VectorXd::LinSpaced(6, -0.3, 0.8)};
  for (std::size_t j = 0; j < weights.size(); ++j) {
    const TraceImages d = direct(weights[j]);
    EXPECT_LT(max_relative(basis.compose(weights[j], GiBasis::Part::i1), d.i1(0)), 2e-6) << j;
  }
  // Away from the inputs the full image is not exact, but the object's I2 is there and small.
  const TraceImages d = direct(weights[0]);
  double i2 = 0, total = 0;
  for (std::size_t k = 0; k < d.p.rgb.size(); ++k) i2 += d.more[0].rgb[k], total += d.full(0).rgb[k];
  EXPECT_GT(i2, 0.0);
  EXPECT_LT(i2, 0.2 * total);
}

TEST_F(GiBasisTest, FullCompositionIsExactAtTheInputs) {
  const GiBasis basis = build_gi_basis(*model_, *world_, settings(), {});
  for (int i : {0, 3}) {
    const Eigen::VectorXd w = model_->material_weights(i);
    EXPECT_LT(max_relative(basis.compose(w), direct(w).full(0)), 2e-6) << i;
  }
}

TEST_F(GiBasisTest, HalfPrecisionCompositionIsWithinItsMeasuredRounding) {
  GiBasis basis = build_gi_basis(*model_, *world_, settings(), {});
  const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(6, 0.05, 0.25);
  const Image exact = basis.compose(w);
  const double rounding = basis.convert_to_half();
  EXPECT_TRUE(basis.is_half());
  EXPECT_GT(rounding, 0.0);
  EXPECT_LT(rounding, 1.0 / 2048);
  const Image half = basis.compose(w);
  EXPECT_NE(half.rgb, exact.rgb);
  EXPECT_LT(max_relative(half, exact), 2e-3);
}

TEST_F(GiBasisTest, FilesRoundTripAndTheCacheResumes) {
  GiBasisOptions options;
  options.cache = dir_->path() / "cache";
  options.batch = 3;
  const GiBasis first = build_gi_basis(*model_, *world_, settings(), options);
  first.save(dir_->path() / "b.safetensors");
  const GiBasis loaded = GiBasis::load(dir_->path() / "b.safetensors");
  const Eigen::VectorXd w = Eigen::VectorXd::LinSpaced(6, 0.0, 0.3);
  EXPECT_EQ(loaded.compose(w).rgb, first.compose(w).rgb);
  EXPECT_EQ(loaded.names(), model_->names());

  // A resumed build reuses the cached images: mark one (a wrong pixel with the right key) and
  // drop another; the next build keeps the first and traces the second again.
  const auto file = [&](int k) {
    char name[40];
    std::snprintf(name, sizeof name, "material-%04d.safetensors", k);
    return options.cache / name;
  };
  ASSERT_TRUE(std::filesystem::exists(file(2)));
  {
    const GiBasis tmp = first;
    Image marked = first.image(GiBasis::Part::all, 2);
    marked.rgb[0] += 1000.0f;
    const Image linear = first.image(GiBasis::Part::i1, 2);
    SafetensorsWriter wr;
    wr.add_metadata("key", gi_basis_key(*model_, *world_, settings()));
    wr.declare("linear", DType::F32, {16, 20, 3});
    wr.declare("full", DType::F32, {16, 20, 3});
    wr.begin(file(2));
    wr.write(std::span<const float>(linear.rgb));
    wr.write(std::span<const float>(marked.rgb));
    wr.commit();
  }
  std::filesystem::remove(file(5));
  const GiBasis resumed = build_gi_basis(*model_, *world_, settings(), options);
  EXPECT_FLOAT_EQ(resumed.image(GiBasis::Part::all, 2).rgb[0], first.image(GiBasis::Part::all, 2).rgb[0] + 1000.0f);
  EXPECT_EQ(resumed.image(GiBasis::Part::all, 5).rgb, first.image(GiBasis::Part::all, 5).rgb);
  EXPECT_TRUE(std::filesystem::exists(file(5)));
  // Other settings do not reuse the entries.
  TraceSettings other = settings();
  other.seed = 8;
  const GiBasis fresh = build_gi_basis(*model_, *world_, other, options);
  EXPECT_NE(fresh.image(GiBasis::Part::all, 2).rgb[0], resumed.image(GiBasis::Part::all, 2).rgb[0]);

  EXPECT_THROW(GiBasis::load(file(1)), Error);
}

// ---- Never a basis that GiBasis::load refuses (issue 28): NaN and infinite pixels
TEST(GiBasisHardening, SaveRefusesNaNOrInfinitePixels) {
  test::TempDir dir;
  Image p(2, 2);
  std::vector<Image> linear(3, Image(2, 2)), full(3, Image(2, 2));
  full[1].rgb[4] = std::numeric_limits<float>::infinity();
  const GiBasis basis(p, linear, full, {"a", "b"}, {});
  try {
    basis.save(dir / "b.safetensors");
    ADD_FAILURE() << "saved";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("b.safetensors: the GI basis has NaN or infinite pixels"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "b.safetensors"));
}

TEST_F(GiBasisTest, AModelWhoseLightOverflowsFloat32IsRefusedBeforeAnythingIsWritten) {
  // Values near the float32 maximum in the model's data (not covered by its checksum): their
  // products along paths overflow the float32 images. The build names the material and writes
  // neither a basis nor a cache entry that could not be read back.
  test::TempDir dir;
  const std::filesystem::path path = dir / "huge.matlas";
  std::filesystem::copy_file(dir_->path() / "m.matlas", path);
  {
    const SafetensorsFile f = SafetensorsFile::open(path);
    const TensorInfo* data = f.find("data");
    ASSERT_TRUE(data && data->dtype == DType::F32);
    std::uint64_t header = 0;
    std::memcpy(&header, f.mapping().data(), 8);
    std::fstream out(path, std::ios::in | std::ios::out | std::ios::binary);
    out.seekp(static_cast<std::streamoff>(8 + header + data->begin));
    const std::vector<float> huge(data->elements(), 3e38f);
    out.write(reinterpret_cast<const char*>(huge.data()), static_cast<std::streamsize>(data->bytes()));
  }
  const Model model = Model::open(path);
  GiBasisOptions options;
  options.cache = dir / "cache";
  try {
    (void)build_gi_basis(model, *world_, settings(), options);
    ADD_FAILURE() << "built";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("huge.matlas: material '" + model.names()[0] +
                                         "' gives NaN or infinite pixels in the GI basis"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(options.cache / "material-0001.safetensors"));
}

TEST(GiBasisHardening, MeasuredValuesTheReaderAcceptsCanOverflowAndAreRefusedNamingTheMaterial) {
  // Every value below the MERL reader's limit (1e15 stored): a build accepts them, but light that
  // bounces on the object several times multiplies them past float32. gi-basis wrote such a basis
  // (and gi refused it); now the build stops, naming the model.
  test::TempDir dir;
  const auto files = write_database(dir / "db", random_catalog(5, 3), null_progress(), MerlDims{8, 8, 16});
  for (const auto& file : files) {
    BrdfTable t = read_merl(file);
    double peak = 0;
    for (const double v : t.stored()) peak = std::max(peak, v);
    for (double& v : t.stored())
      if (v > 0) v *= 9e14 / peak;
    write_merl(file, t, /*allow_nonstandard_dims=*/true);
  }
  BuildOptions options;
  options.dim = 2;
  build_model(MaterialSet::open({dir / "db"}), options, dir / "huge.matlas");
  const Model model = Model::open(dir / "huge.matlas");
  const World world(load_scene("box", "sphere"));
  TraceSettings s;
  s.width = 32;
  s.height = 24;
  s.spp = 16;
  try {
    (void)build_gi_basis(model, world, s, {});
    ADD_FAILURE() << "built";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("huge.matlas: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gives NaN or infinite pixels in the GI basis"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace matlas::atlas
