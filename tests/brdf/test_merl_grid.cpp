// The MERL grid against an independent, literal transcription of the reference reader's
// coordinate conversion (spherical angles in, rotations about fixed axes) and index mapping.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "brdf/brdf_table.h"
#include "brdf/merl_grid.h"

namespace matlas {
namespace {

// --- Reference: MERL BRDFRead.cpp, written out independently with plain arrays. ---
void ref_rotate(const double v[3], const double axis[3], double angle, double out[3]) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double dot = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
  const double cross[3] = {axis[1] * v[2] - axis[2] * v[1], axis[2] * v[0] - axis[0] * v[2],
                           axis[0] * v[1] - axis[1] * v[0]};
  for (int i = 0; i < 3; ++i) out[i] = v[i] * c + axis[i] * dot * (1 - c) + cross[i] * s;
}

void ref_half_diff(double ti, double fi, double to, double fo, double& th, double& td,
                   double& fd) {
  double in[3] = {std::sin(ti) * std::cos(fi), std::sin(ti) * std::sin(fi), std::cos(ti)};
  double out[3] = {std::sin(to) * std::cos(fo), std::sin(to) * std::sin(fo), std::cos(to)};
  double half[3] = {(in[0] + out[0]) / 2, (in[1] + out[1]) / 2, (in[2] + out[2]) / 2};
  const double len = std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
  for (double& h : half) h /= len;
  th = std::acos(half[2]);
  const double fh = std::atan2(half[1], half[0]);
  const double binormal[3] = {0, 1, 0}, normal[3] = {0, 0, 1};
  double tmp[3], diff[3];
  ref_rotate(in, normal, -fh, tmp);
  ref_rotate(tmp, binormal, -th, diff);
  td = std::acos(diff[2]);
  fd = std::atan2(diff[1], diff[0]);
}

int ref_index(double ti, double fi, double to, double fo) {
  double th, td, fd;
  ref_half_diff(ti, fi, to, fo, th, td, fd);
  int ih = 0;
  if (th > 0.0) {
    ih = static_cast<int>(std::sqrt(th / (M_PI / 2.0) * 90.0 * 90.0));
    ih = std::clamp(ih, 0, 89);
  }
  int id = std::clamp(static_cast<int>(td / (M_PI * 0.5) * 90), 0, 89);
  if (fd < 0.0) fd += M_PI;
  int ip = std::clamp(static_cast<int>(fd / M_PI * 360 / 2), 0, 179);
  return ip + id * 180 + ih * 180 * 90;
}
// --- End of reference. ---

Vec3 spherical(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

TEST(MerlGrid, LookupIndexMatchesReferenceOn100kRandomPairs) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> theta(0.0, M_PI / 2), phi(0.0, 2 * M_PI);
  const MerlDims dims;
  int mismatches = 0;
  for (int n = 0; n < 100000; ++n) {
    const double ti = theta(rng), fi = phi(rng), to = theta(rng), fo = phi(rng);
    const std::size_t ours = bin_of(dims, spherical(ti, fi), spherical(to, fo));
    if (ours != static_cast<std::size_t>(ref_index(ti, fi, to, fo))) ++mismatches;
  }
  // Both compute the same expressions; only a last-bit difference right on a bin boundary
  // could change an index.
  EXPECT_LE(mismatches, 2);
}

TEST(MerlGrid, LookupIsReciprocal) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> theta(0.0, M_PI / 2), phi(0.0, 2 * M_PI);
  BrdfTable table(MerlDims{});
  for (std::size_t i = 0; i < table.size(); ++i) table.stored()[i] = static_cast<double>(i % 9973);
  int differ = 0;
  for (int n = 0; n < 100000; ++n) {
    const double pa = phi(rng), ta = theta(rng), pb = phi(rng), tb = theta(rng);  // sequenced
    const Vec3 a = spherical(ta, pa), b = spherical(tb, pb);
    if (!(table.lookup(a, b) == table.lookup(b, a)).all()) ++differ;
  }
  EXPECT_LE(differ, 10);  // phi_d exactly on a bin edge after folding, at most a handful
}

TEST(MerlGrid, HalfDiffRoundTrip) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  for (int n = 0; n < 1000; ++n) {
    HalfDiffAngles a;
    a.theta_h = u(rng) * M_PI / 2;
    a.phi_h = (u(rng) - 0.5) * 2 * M_PI;
    a.theta_d = u(rng) * M_PI / 2;
    a.phi_d = (u(rng) - 0.5) * 2 * M_PI;
    const DirectionPair d = from_half_diff(a);
    EXPECT_NEAR(d.wi.norm(), 1.0, 1e-12);
    const HalfDiffAngles b = to_half_diff(d.wi, d.wo);
    EXPECT_NEAR(b.theta_h, a.theta_h, 1e-9);
    EXPECT_NEAR(b.theta_d, a.theta_d, 1e-9);
    EXPECT_NEAR(std::remainder(b.phi_d - a.phi_d, 2 * M_PI), 0.0, 1e-9);
  }
}

TEST(MerlGrid, BinCentresMapToTheirOwnBin) {
  const MerlDims dims;
  for (int i = 0; i < 90; i += 7)
    for (int j = 0; j < 90; j += 11)
      for (int k = 0; k < 180; k += 13) {
        const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
        EXPECT_EQ(bin_of(dims, d.wi, d.wo), dims.flat(i, j, k)) << i << " " << j << " " << k;
      }
}

TEST(MerlGrid, CosineFactorsMatchTheDirectionsOfEveryBinCentre) {
  // Independent expectation: the directions from_half_diff gives at each bin centre.
  for (const MerlDims dims : {MerlDims{}, MerlDims{17, 9, 31}}) {
    const std::vector<double> c = bin_cosine_factors(dims);
    ASSERT_EQ(c.size(), dims.bins());
    double max_error = 0.0;
    std::size_t positive = 0;
    for (int i = 0; i < dims.theta_h; ++i)
      for (int j = 0; j < dims.theta_d; ++j)
        for (int k = 0; k < dims.phi_d; ++k) {
          const DirectionPair d = from_half_diff(bin_centre(dims, i, j, k));
          const double expected = std::max(0.0, d.wi.z()) * std::max(0.0, d.wo.z());
          max_error = std::max(max_error, std::abs(c[dims.flat(i, j, k)] - expected));
          positive += expected > 0.0;
        }
    EXPECT_LT(max_error, 1e-12) << dims.to_string();
    EXPECT_GT(positive, dims.bins() / 2);  // most bins face up on both sides; the rest are 0
  }
}

TEST(BrdfTable, MissingValuesAreMaskedNotUsed) {
  BrdfTable table(MerlDims{});
  for (std::size_t b = 0; b < table.bins(); ++b)
    for (int c = 0; c < 3; ++c) table.set_value(c, b, 0.5);
  const Vec3 wi = spherical(0.3, 0.1), wo = spherical(0.4, 2.0);
  const std::size_t bin = bin_of(table.dims(), wi, wo);
  table.set_missing(1, bin);
  bool all = true;
  const Rgb v = table.lookup(wi, wo, &all);
  EXPECT_FALSE(all);
  EXPECT_DOUBLE_EQ(v[0], 0.5);
  EXPECT_EQ(v[1], 0.0);
  EXPECT_EQ(table.missing_count(), 1u);
  // The smooth lookup skips the missing neighbour: a constant table stays constant.
  EXPECT_NEAR(table.lookup_smooth(wi, wo)[1], 0.5, 1e-12);
}

TEST(BrdfTable, SmoothLookupInterpolatesLinearFieldsExactly) {
  // A table linear in the phi_d bin coordinate is reproduced between bin centres.
  const MerlDims dims;
  BrdfTable table(dims);
  for (int i = 0; i < 90; ++i)
    for (int j = 0; j < 90; ++j)
      for (int k = 0; k < 180; ++k)
        for (int c = 0; c < 3; ++c) table.set_value(c, dims.flat(i, j, k), 1.0 + j);
  HalfDiffAngles a = bin_centre(dims, 40, 20, 50);
  a.theta_d += 0.25 * (M_PI / 2) / 90;  // a quarter bin further in theta_d
  const DirectionPair d = from_half_diff(a);
  EXPECT_NEAR(table.lookup_smooth(d.wi, d.wo)[0], 21.25, 1e-6);
}

}  // namespace
}  // namespace matlas
