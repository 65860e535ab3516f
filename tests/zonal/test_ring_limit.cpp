// The window per theta_o sample (zonal/ring_limit.h): a slice that does not ring is left as it is,
// a ringing one is lifted to the floor by the least smoothing (checked with the reconstruction's
// own code, zonal::reconstruct, on a finer grid than the limiter's), a dip no window can lift gets
// Hann, the projector applies it, and the coefficient file keeps its floor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "brdf/analytic.h"
#include "brdf/tabulate.h"
#include "core/error.h"
#include "support/temp_dir.h"
#include "zonal/coefficient_file.h"
#include "zonal/projection.h"
#include "zonal/ring_limit.h"
#include "zonal/window.h"

namespace matlas::zonal {
namespace {

/// The reconstructed slice at sample t on a grid of rows x columns midpoints over the sphere
/// (theta in [0, pi], phi in [0, pi]), with band l weighted by window[l] (none: as stored):
/// {the lowest value over channels, the area-weighted median over the upper hemisphere of the
/// channels' mean}.
std::pair<double, double> slice_extent(const ZonalBasis& basis, const ZonalCoefficients& c, int t, int rows,
                                       int columns, const std::vector<double>* window = nullptr) {
  const double theta_o = ZonalCoefficients::theta_o(t, c.theta_o_count);
  double lowest = 1e300;
  std::vector<std::pair<double, double>> upper;
  for (int i = 0; i < rows; ++i)
    for (int k = 0; k < columns; ++k) {
      const double theta = (i + 0.5) * kPi / rows, phi = (k + 0.5) * kPi / columns;
      const Vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const Rgb v = reconstruct(basis, c, theta_o, w, window);
      lowest = std::min(lowest, v.minCoeff());
      if (w.z() > 0) upper.emplace_back(v.mean(), std::sin(theta));
    }
  std::sort(upper.begin(), upper.end());
  double total = 0, below = 0, median = 0;
  for (const auto& u : upper) total += u.second;
  for (const auto& [value, weight] : upper) {
    below += weight;
    median = value;
    if (below >= 0.5 * total) break;
  }
  return {lowest, median};
}

/// Band l's factor 1 - s (1 - h_l) for bands 0..L.
std::vector<double> blend(int L, double s) {
  std::vector<double> w = band_window(BandWindow::hann, L);
  for (double& v : w) v = 1.0 - s * (1.0 - v);
  return w;
}

ProjectionSettings settings(int bands, std::vector<double> lobes = {}) {
  ProjectionSettings s;
  s.bands = bands;
  s.theta_o_count = 8;
  s.lobes = std::move(lobes);
  return s;
}

TEST(RingLimit, LeavesASliceThatDoesNotRingAsItIs) {
  // A Lambertian slice, (a / pi) max(cos, 0), at L = 16: its truncation dips below zero by far less
  // than 5 % of its median level (a / 2 pi).
  const ZonalProjector p(settings(16));
  const ZonalCoefficients plain = p.project(tabulate(Lambertian{Rgb(0.6, 0.5, 0.4)}));
  ZonalCoefficients limited = plain;
  const std::vector<double> ts = RingLimiter(p.basis(), plain, RingLimit{0.05}).apply(limited);
  for (double t : ts) EXPECT_EQ(t, 0.0);
  EXPECT_EQ(limited.values, plain.values);
}

TEST(RingLimit, LiftsARingingSliceToTheFloorWithTheLeastSmoothing) {
  // A glossy plastic (alpha 0.08 over a diffuse base) at L = 8 with a lobe: the truncation rings
  // below the floor at grazing samples; after the limit the slice is above -floor x the level (the
  // median of its Hann reconstruction), also on a finer grid than the limiter's, and a little less
  // smoothing would not be.
  const ZonalProjector p(settings(8, {256.0}));
  const ZonalCoefficients plain = p.project(tabulate(RoughPlastic{Rgb(0.5, 0.3, 0.2), 0.08, 1.5, 1.0}));
  const double floor = 0.05;
  ZonalCoefficients limited = plain;
  const std::vector<double> ts = RingLimiter(p.basis(), plain, RingLimit{floor}).apply(limited);
  const std::vector<double> hann = blend(8, 1.0);
  int lifted = 0;
  for (int t = 0; t < plain.theta_o_count; ++t) {
    const double s = ts[static_cast<std::size_t>(t)];
    ASSERT_GE(s, 0.0);
    ASSERT_LE(s, 1.0);
    if (s == 1.0) continue;  // Hann: no weight reaches the floor (not expected here)
    const double level = slice_extent(p.basis(), plain, t, 64, 64, &hann).second;
    const double lowest = -floor * level;
    const auto [stored, median] = slice_extent(p.basis(), limited, t, 64, 64);
    EXPECT_GE(stored, lowest * (1.0 + 1e-6) - 1e-12) << "sample " << t;
    if (s == 0.0) continue;
    ++lifted;
    // The stored coefficients are the plain ones times 1 - s (1 - h_l).
    const std::vector<double> w = blend(8, s);
    EXPECT_NEAR(slice_extent(p.basis(), plain, t, 64, 64, &w).first, stored, 1e-9 * std::abs(stored) + 1e-12);
    // Finer grid: the floor holds within a tenth of it.
    EXPECT_GE(slice_extent(p.basis(), limited, t, 96, 96).first, 1.1 * lowest) << "sample " << t;
    // Less smoothing would ring below the floor.
    const std::vector<double> less = blend(8, std::max(0.0, s - 0.02));
    EXPECT_LT(slice_extent(p.basis(), plain, t, 64, 64, &less).first, lowest) << "sample " << t;
  }
  EXPECT_GE(lifted, 2);  // measured: the grazing samples
}

TEST(RingLimit, GivesHannWhereNoWindowLiftsTheDip) {
  // A GGX conductor of alpha 0.05 at L = 6, no lobes: its slice is nearly zero away from the peak
  // (median about 0), so no weight keeps the truncation above -0 x median: Hann, the family's end.
  const ZonalProjector p(settings(6));
  const ZonalCoefficients plain = p.project(tabulate(GgxConductor{Rgb(0.9, 0.9, 0.9), 0.05}));
  ZonalCoefficients limited = plain;
  const std::vector<double> ts = RingLimiter(p.basis(), plain, RingLimit{0.0}).apply(limited);
  const std::vector<double> hann = band_window(BandWindow::hann, 6);
  int hanned = 0;
  for (int t = 0; t < plain.theta_o_count; ++t) {
    if (ts[static_cast<std::size_t>(t)] != 1.0) continue;
    ++hanned;
    for (std::size_t j = 0; j < plain.zonal_size(); ++j)
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(limited.at(t, j)[ch], hann[static_cast<std::size_t>(p.basis().band(j))] * plain.at(t, j)[ch],
                    1e-12 * std::abs(plain.at(t, j)[ch]) + 1e-15);
  }
  EXPECT_GE(hanned, 4);
}

TEST(RingLimit, TheProjectorAppliesItAndTheFileKeepsItsFloor) {
  ProjectionSettings s = settings(8, {64.0, 256.0});
  const ZonalProjector plain(s);
  s.ring_floor = 0.05;
  const ZonalProjector limited(s);
  const BrdfTable a = tabulate(RoughPlastic{Rgb(0.5, 0.3, 0.2), 0.08, 1.5, 1.0});
  const BrdfTable b = tabulate(GgxConductor{Rgb(1.0, 0.8, 0.4), 0.1});
  ZonalCoefficients expected = plain.project(a);
  const std::vector<double> ts = RingLimiter(plain.basis(), expected, RingLimit{0.05}).apply(expected);
  ASSERT_GT(*std::max_element(ts.begin(), ts.end()), 0.0);  // the limit changes this table
  EXPECT_NE(expected.values, plain.project(a).values);
  EXPECT_EQ(limited.project(a).values, expected.values);
  const std::vector<ZonalCoefficients> many = limited.project_many(
      [&](std::uint32_t bin, int channel, double* out) {
        out[0] = a.bin_rgb(bin)[channel];
        out[1] = b.bin_rgb(bin)[channel];
      },
      2);
  for (std::size_t v = 0; v < expected.values.size(); ++v)
    EXPECT_NEAR(many[0].values[v], expected.values[v], 1e-9 * (std::abs(expected.values[v]) + 1e-6));

  test::TempDir dir;
  CoefficientSet set;
  set.settings = s;
  set.names = {"plastic", "gold"};
  set.materials = many;
  write_coefficients(dir / "c.safetensors", set, DType::F32);
  EXPECT_EQ(read_coefficients(dir / "c.safetensors").settings.ring_floor, 0.05);
  set.settings.ring_floor = -1.0;
  write_coefficients(dir / "d.safetensors", set, DType::F32);
  EXPECT_LT(read_coefficients(dir / "d.safetensors").settings.ring_floor, 0.0);
}

TEST(RingLimit, RefusesBadSettingsAndOtherLayouts) {
  const ZonalProjector p(settings(4));
  ZonalCoefficients c = p.project(tabulate(Lambertian{Rgb(0.5, 0.5, 0.5)}));
  EXPECT_THROW(RingLimiter(p.basis(), c, RingLimit{-0.1}), Error);
  EXPECT_THROW(RingLimiter(p.basis(), c, RingLimit{0.05, 63, 64}), Error);  // odd rows
  EXPECT_THROW(RingLimiter(ZonalBasis(2), c, RingLimit{0.05}), Error);
  const RingLimiter limiter(p.basis(), c, RingLimit{0.05});
  ZonalCoefficients other = ZonalProjector(settings(4, {64.0})).project(tabulate(Lambertian{Rgb(0.5, 0.5, 0.5)}));
  EXPECT_THROW(limiter.apply(other), Error);
  ProjectionSettings bad = settings(4);
  bad.ring_floor = 2.0;
  EXPECT_THROW(ZonalProjector{bad}, Error);
}

}  // namespace
}  // namespace matlas::zonal
