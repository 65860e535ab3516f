// The preview bases' disk cache (server/basis_previews.h): a cached basis is reused only when it
// was rendered with the sampling the server would use now; one from another sampler or mixture
// (an older matlas) is rendered again and replaced, so previews always equal direct renders.
#include <gtest/gtest.h>

#include <filesystem>

#include "atlas/model_basis.h"
#include "atlas/sampling_fit.h"
#include "render/image_basis.h"
#include "render/render.h"
#include "render/scene.h"
#include "small_model.h"
#include "support/temp_dir.h"

namespace matlas::server {
namespace {

BasisPreviewOptions cached_options(const std::filesystem::path& cache) {
  BasisPreviewOptions po;
  po.environments = {"constant"};
  po.objects = {"sphere"};
  po.size = 24;
  po.spp = 2;
  po.cache_dir = cache;
  return po;
}

std::string recorded_sampling(const std::filesystem::path& path) {
  return render::ImageBasis::open(path).metadata().at("sampling_mixture");
}

TEST(BasisCache, ABasisFromAnotherSamplerIsRenderedAgain) {
  test::TempDir dir("matlas-basis-cache");
  const Model model = test::build_small_model(dir.path(), 5, 7);
  const BasisPreviewOptions po = cached_options(dir.path() / "bases");
  render::RenderSettings now;
  now.width = now.height = po.size;
  now.spp = po.spp;
  now.seed = po.seed;
  const std::string expected = atlas::sampling_record(atlas::model_render_settings(model, now));
  ASSERT_NE(expected.find("light_and_lobe"), std::string::npos) << expected;  // the default sampler

  std::filesystem::path path;
  {
    BasisPreviews previews(model, po);
    previews.prepare_default();
    path = previews.cache_path("constant", "sphere");
    ASSERT_TRUE(std::filesystem::exists(path));
    EXPECT_EQ(recorded_sampling(path), expected);
  }
  // Replace the cached file by a basis of the same scene rendered with the stratified sampler.
  render::RenderSettings older = now;
  older.sampler = render::Sampler::stratified;
  render::SceneDescription desc;
  desc.environment = "constant";
  desc.object = "sphere";
  atlas::render_basis(model, render::Scene(desc), older).save(path, render::BasisPrecision::f16);
  ASSERT_NE(recorded_sampling(path), expected);

  BasisPreviews again(model, po);
  again.prepare_default();
  EXPECT_EQ(recorded_sampling(path), expected);  // rendered anew with the current sampling
}

TEST(BasisCache, TheRecordNamesTheSamplerTheMixtureAndTheProfile) {
  render::RenderSettings a;
  render::RenderSettings b = a;
  b.sampler = render::Sampler::stratified;
  EXPECT_NE(atlas::sampling_record(a), atlas::sampling_record(b));
  b = a;
  b.mixture.lobes.front().second += 0.01;
  EXPECT_NE(atlas::sampling_record(a), atlas::sampling_record(b));
  b = a;
  b.mixture.set_profile({1.0, 2.0, 3.0}, 0.1);
  render::RenderSettings c = a;
  c.mixture.set_profile({1.0, 2.0, 4.0}, 0.1);
  EXPECT_NE(atlas::sampling_record(b), atlas::sampling_record(c));  // same share, other profile
  EXPECT_EQ(atlas::sampling_record(a), atlas::sampling_record(render::RenderSettings{}));
}

}  // namespace
}  // namespace matlas::server
