// ProgressiveTrace (the scene view refined at rest) against independent expectations: its image is
// the spp-weighted mean of independent traces with the pass seeds, it converges to the furnace's
// albedo x radiance, and its error estimate falls as passes come in.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "brdf/tabulate.h"
#include "core/error.h"
#include "pathtrace/progressive_trace.h"
#include "render/material.h"

namespace matlas::pathtrace {
namespace {

SceneSpec furnace() {
  SceneSpec s;
  s.camera.position = Vec3(0, 0, 10);
  s.camera.target = Vec3::Zero();
  s.camera.fov_degrees = 8.0;
  s.environment.constant = Rgb::Constant(0.7);
  ObjectSpec o;
  o.shape = "sphere";
  o.surface.kind = SurfaceSpec::Kind::measured;
  s.objects.push_back(o);
  return s;
}

struct Fixture {
  BrdfTable table = tabulate([](const Vec3&, const Vec3&) -> Rgb { return Rgb(0.9, 0.5, 0.2) / kPi; });
  std::shared_ptr<const World> world = std::make_shared<const World>(furnace());
  std::shared_ptr<const render::MaterialList> bank = std::make_shared<const render::MaterialList>(
      render::MaterialList::owning({std::make_shared<const render::TableMaterial>(table)}));
  ProgressiveTraceSettings settings() const {
    ProgressiveTraceSettings s;
    s.trace.width = s.trace.height = 9;
    s.trace.spp = 2;
    s.trace.seed = 5;
    s.limits.max_pass_spp = 8;
    s.adaptive.enabled = false;  // the passes' bookkeeping (adaptive sampling: the tests below)
    return s;
  }
};

TEST(ProgressiveTrace, ImageIsTheSampleWeightedMeanOfIndependentPasses) {
  const Fixture f;
  ProgressiveTrace p(f.world, f.bank, f.settings());
  // Passes by hand: refine(0) adds one pass per call (the first of 2 spp, then what fits: at
  // least the first pass's samples).
  std::vector<int> spps;
  int before = 0;
  for (int k = 0; k < 4; ++k) {
    const render::RefinementState st = p.refine(0.0);
    spps.push_back(st.spp - before);
    before = st.spp;
    EXPECT_EQ(st.passes, k + 1);
  }
  // The same passes traced independently with the pass seeds, weighted by their samples.
  Image expected(9, 9);
  double total = 0;
  for (int k = 0; k < 4; ++k) {
    TraceSettings t = f.settings().trace;
    t.spp = spps[static_cast<std::size_t>(k)];
    t.seed = ProgressiveTrace::pass_seed(5, k);
    EXPECT_NE(t.seed, 5u) << "no pass reuses the basis's seed";
    const Image pass = trace(*f.world, f.bank.get(), t).full(0);
    for (std::size_t i = 0; i < expected.rgb.size(); ++i) expected.rgb[i] += static_cast<float>(t.spp) * pass.rgb[i];
    total += t.spp;
  }
  const Image got = p.image();
  for (std::size_t i = 0; i < expected.rgb.size(); ++i)
    EXPECT_NEAR(got.rgb[i], expected.rgb[i] / total, 1e-5 * (1.0 + std::abs(got.rgb[i]))) << i;
}

TEST(ProgressiveTrace, ConvergesToTheFurnaceAndItsErrorEstimateFalls) {
  const Fixture f;
  ProgressiveTraceSettings s = f.settings();
  s.trace.spp = 64;  // passes of 64 spp: 512 after eight
  s.limits.max_pass_spp = 64;
  ProgressiveTrace p(f.world, f.bank, s);
  EXPECT_FALSE(std::isfinite(p.refine(0.0).relative_error)) << "one pass: no estimate yet";
  const double early = p.refine(0.0).relative_error;
  render::RefinementState st;
  for (int k = 0; k < 6; ++k) st = p.refine(0.0);
  EXPECT_LT(st.relative_error, early);
  const Image im = p.image();
  const Rgb albedo(0.9, 0.5, 0.2);
  EXPECT_EQ(st.spp, 512);
  for (int c = 0; c < 3; ++c) {
    double centre = 0;
    for (int y = 3; y <= 5; ++y)
      for (int x = 3; x <= 5; ++x) centre += im.pixel(x, y)[c] / 9.0;
    EXPECT_NEAR(centre, 0.7 * albedo[c], 0.02 * albedo[c]) << c;
  }
}

TEST(ProgressiveTrace, APixelsShareIsItsNumberOfSamples) {
  // Sample s of pixel p draws from the stream (seed, p, s) whatever the other pixels take, so a
  // pixel that takes n samples equals the uniform trace of n spp there.
  const Fixture f;
  TraceSettings t = f.settings().trace;
  t.spp = 4;
  auto shares = std::make_shared<std::vector<double>>(81, 1.0);
  (*shares)[40] = 2.0;   // 8 samples
  (*shares)[41] = 0.25;  // 1
  t.pixel_samples = shares;
  const Image adaptive = trace(*f.world, f.bank.get(), t).full(0);
  t.pixel_samples = nullptr;
  const Image four = trace(*f.world, f.bank.get(), t).full(0);
  t.spp = 8;
  const Image eight = trace(*f.world, f.bank.get(), t).full(0);
  t.spp = 1;
  const Image one = trace(*f.world, f.bank.get(), t).full(0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(adaptive.rgb[3 * 40 + c], eight.rgb[3 * 40 + c]);
    EXPECT_FLOAT_EQ(adaptive.rgb[3 * 41 + c], one.rgb[3 * 41 + c]);
    EXPECT_FLOAT_EQ(adaptive.rgb[3 * 39 + c], four.rgb[3 * 39 + c]);
  }
  t.pixel_samples = std::make_shared<std::vector<double>>(80, 1.0);
  EXPECT_THROW(trace(*f.world, f.bank.get(), t), Error);
}

TEST(ProgressiveTrace, TheTrialChoosesSharesAndTheRefinementRestartsWithThem) {
  const Fixture f;
  ProgressiveTraceSettings s = f.settings();
  s.adaptive.enabled = true;
  s.trace.spp = 8;  // the trial takes a pass of at least min_trial_spp (8) after the first
  ProgressiveTrace p(f.world, f.bank, s);
  p.refine(0.0);
  EXPECT_EQ(p.pixel_samples(), nullptr);  // the first pass is uniform
  const render::RefinementState st = p.refine(0.0);
  ASSERT_NE(p.pixel_samples(), nullptr);
  EXPECT_EQ(st.passes, 1);  // the trial's halves are dropped
  // What is shown is one trace with the shares, none of the halves' samples in it.
  TraceSettings t = s.trace;
  t.spp = st.spp;
  t.seed = ProgressiveTrace::pass_seed(5, 1) ^ 0x94D049BB133111EBull;
  t.pixel_samples = p.pixel_samples();
  const Image expected = trace(*f.world, f.bank.get(), t).full(0), got = p.image();
  for (std::size_t i = 0; i < expected.rgb.size(); ++i) EXPECT_NEAR(got.rgb[i], expected.rgb[i], 1e-5) << i;
  double mean = 0;
  for (const double share : *p.pixel_samples()) mean += share / 81.0;
  EXPECT_NEAR(mean, 1.0, 1e-9);
  EXPECT_EQ(p.refine(0.0).passes, 2);
  // With passes of fewer than min_trial_spp samples the trial waits.
  s.trace.spp = 2;
  ProgressiveTrace early(f.world, f.bank, s);
  early.refine(0.0);
  early.refine(0.0);
  EXPECT_EQ(early.state().passes, 2);
  EXPECT_EQ(early.pixel_samples(), nullptr);
}


TEST(ProgressiveTrace, RegionsAreWhatEachPixelSeesFirst) {
  // The floor scene at 32 x 24: the sphere (object 0) in the middle, the floor (1) at the bottom,
  // the wall (2) at the top; pixels on the sphere's silhouette see two objects (0).
  const Fixture f;
  ProgressiveTraceSettings s = f.settings();
  s.trace.width = 32;
  s.trace.height = 24;
  const ProgressiveTrace p(std::make_shared<const World>(load_scene("floor", "sphere")), f.bank, s);
  const std::vector<std::uint8_t>& r = p.regions();
  ASSERT_EQ(r.size(), 32u * 24u);
  EXPECT_EQ(r[12 * 32 + 16], 1);
  EXPECT_EQ(r[23 * 32 + 0], 2);
  EXPECT_EQ(r[0 * 32 + 0], 3);
  int silhouette = 0;
  for (const std::uint8_t label : r) silhouette += label == 0;
  EXPECT_GT(silhouette, 10);
  EXPECT_LT(silhouette, 120);
}

TEST(ProgressiveTrace, TheDenoisedImageIsCloserToALongTraceAndKeepsSilhouettes) {
  // The floor scene at 32 x 24 with a grey measured sphere, refined to 32 spp, against a
  // 1024-spp trace (other seeds): the denoised image (its bias included) is nearer than the mean.
  const BrdfTable grey = tabulate([](const Vec3&, const Vec3&) -> Rgb { return Rgb::Constant(0.5 / kPi); });
  const auto bank = std::make_shared<const render::MaterialList>(
      render::MaterialList::owning({std::make_shared<const render::TableMaterial>(grey)}));
  const auto world = std::make_shared<const World>(load_scene("floor", "sphere"));
  ProgressiveTraceSettings s;
  s.trace.width = 32;
  s.trace.height = 24;
  s.trace.spp = 8;
  s.trace.seed = 21;
  s.limits.max_pass_spp = 8;
  s.adaptive.enabled = false;
  ProgressiveTrace p(world, bank, s);
  EXPECT_FALSE(std::isfinite(p.denoised().relative_error)) << "one half is empty before two passes";
  while (p.state().spp < 32) p.refine(0.0);
  TraceSettings long_trace = s.trace;
  long_trace.spp = 1024;
  long_trace.seed = 99;
  const Image reference = trace(*world, bank.get(), long_trace).full(0);
  const Image mean = p.image();
  const render::DenoiseResult d = p.denoised();
  const auto error = [&](const Image& im) {
    double e = 0, r = 0;
    for (std::size_t i = 0; i < im.rgb.size(); ++i) {
      e += (double(im.rgb[i]) - reference.rgb[i]) * (double(im.rgb[i]) - reference.rgb[i]);
      r += double(reference.rgb[i]) * reference.rgb[i];
    }
    return std::sqrt(e / r);
  };
  EXPECT_LT(error(d.image), 0.8 * error(mean)) << error(d.image) << " " << error(mean);
  EXPECT_LT(d.relative_error, p.state().relative_error);
  // Silhouette pixels are not averaged with others: each is its mean, or (a firefly in a half,
  // removed before filtering) darker than it.
  int silhouette = 0, darker = 0;
  const auto luminance = [](const float* v) { return 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2]; };
  for (std::size_t px = 0; px < p.regions().size(); ++px) {
    if (p.regions()[px] != 0) continue;
    ++silhouette;
    bool same = true;
    for (std::size_t c = 0; c < 3; ++c)
      same = same && std::abs(d.image.rgb[3 * px + c] - mean.rgb[3 * px + c]) <= 1e-5f * (1.0f + mean.rgb[3 * px + c]);
    if (same) continue;
    ++darker;
    EXPECT_LT(luminance(&d.image.rgb[3 * px]), luminance(&mean.rgb[3 * px])) << px;
  }
  EXPECT_GT(silhouette, 10);
  EXPECT_LE(darker, silhouette / 5) << "only fireflies change at a silhouette";
}

}  // namespace
}  // namespace matlas::pathtrace
