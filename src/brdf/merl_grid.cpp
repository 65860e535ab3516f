#include "brdf/merl_grid.h"

#include <algorithm>
#include <cmath>

namespace matlas {

std::string MerlDims::to_string() const {
  return std::to_string(theta_h) + "x" + std::to_string(theta_d) + "x" + std::to_string(phi_d);
}

namespace {

/// Rotation of v about a unit axis by angle (Rodrigues), as in MERL's rotate_vector.
Vec3 rotate(const Vec3& v, const Vec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + axis * (axis.dot(v) * (1.0 - c)) + axis.cross(v) * s;
}

int clamp_index(double t, int n) {
  if (!(t > 0.0)) return 0;  // also maps NaN to 0
  return std::min(static_cast<int>(t), n - 1);
}

}  // namespace

HalfDiffAngles to_half_diff(const Vec3& wi, const Vec3& wo) {
  const Vec3 h = (wi + wo).normalized();
  HalfDiffAngles a;
  a.theta_h = std::acos(std::clamp(h.z(), -1.0, 1.0));
  a.phi_h = std::atan2(h.y(), h.x());
  const Vec3 tmp = rotate(wi, Vec3::UnitZ(), -a.phi_h);
  const Vec3 diff = rotate(tmp, Vec3::UnitY(), -a.theta_h);
  a.theta_d = std::acos(std::clamp(diff.z(), -1.0, 1.0));
  a.phi_d = std::atan2(diff.y(), diff.x());
  return a;
}

DirectionPair from_half_diff(const HalfDiffAngles& a) {
  const Vec3 diff(std::sin(a.theta_d) * std::cos(a.phi_d), std::sin(a.theta_d) * std::sin(a.phi_d),
                  std::cos(a.theta_d));
  const Vec3 wi = rotate(rotate(diff, Vec3::UnitY(), a.theta_h), Vec3::UnitZ(), a.phi_h);
  const Vec3 h(std::sin(a.theta_h) * std::cos(a.phi_h), std::sin(a.theta_h) * std::sin(a.phi_h),
               std::cos(a.theta_h));
  const Vec3 wo = 2.0 * wi.dot(h) * h - wi;
  return {wi, wo.normalized()};
}

int theta_h_index(double theta_h, int n) {
  if (theta_h <= 0.0) return 0;
  return clamp_index(std::sqrt(theta_h / (kPi / 2.0) * n * n), n);
}

int theta_d_index(double theta_d, int n) { return clamp_index(theta_d / (kPi * 0.5) * n, n); }

int phi_d_index(double phi_d, int n) {
  if (phi_d < 0.0) phi_d += kPi;
  return clamp_index(phi_d / kPi * n, n);
}

double theta_h_coordinate(double theta_h, int n) {
  return theta_h <= 0.0 ? 0.0 : std::sqrt(theta_h / (kPi / 2.0)) * n;
}

double theta_d_coordinate(double theta_d, int n) { return theta_d / (kPi / 2.0) * n; }

double phi_d_coordinate(double phi_d, int n) {
  if (phi_d < 0.0) phi_d += kPi;
  if (phi_d >= kPi) phi_d -= kPi;
  return phi_d / kPi * n;
}

double theta_h_centre(int i, int n) {
  const double u = (i + 0.5) / n;
  return u * u * (kPi / 2.0);
}

double theta_d_centre(int j, int n) { return (j + 0.5) / n * (kPi / 2.0); }

double phi_d_centre(int k, int n) { return (k + 0.5) / n * kPi; }

HalfDiffAngles bin_centre(const MerlDims& dims, int i, int j, int k) {
  HalfDiffAngles a;
  a.theta_h = theta_h_centre(i, dims.theta_h);
  a.theta_d = theta_d_centre(j, dims.theta_d);
  a.phi_d = phi_d_centre(k, dims.phi_d);
  return a;
}

std::vector<double> bin_cosine_factors(const MerlDims& dims) {
  // With phi_h = 0 (a rotation about the normal changes neither cosine), from_half_diff gives
  // wi = R_y(theta_h) d for the difference vector d, and wo = 2 (wi . h) h - wi with wi . h =
  // cos theta_d. Their z components are A - B and A + B, with A = cos theta_h cos theta_d and
  // B = sin theta_h sin theta_d cos phi_d: separable, so no trigonometry per bin.
  std::vector<double> cos_h(static_cast<std::size_t>(dims.theta_h)), sin_h(cos_h.size());
  std::vector<double> cos_d(static_cast<std::size_t>(dims.theta_d)), sin_d(cos_d.size());
  std::vector<double> cos_phi(static_cast<std::size_t>(dims.phi_d));
  for (int i = 0; i < dims.theta_h; ++i) {
    const double t = theta_h_centre(i, dims.theta_h);
    cos_h[static_cast<std::size_t>(i)] = std::cos(t);
    sin_h[static_cast<std::size_t>(i)] = std::sin(t);
  }
  for (int j = 0; j < dims.theta_d; ++j) {
    const double t = theta_d_centre(j, dims.theta_d);
    cos_d[static_cast<std::size_t>(j)] = std::cos(t);
    sin_d[static_cast<std::size_t>(j)] = std::sin(t);
  }
  for (int k = 0; k < dims.phi_d; ++k) cos_phi[static_cast<std::size_t>(k)] = std::cos(phi_d_centre(k, dims.phi_d));
  std::vector<double> c(dims.bins());
  double* out = c.data();
  for (std::size_t i = 0; i < cos_h.size(); ++i)
    for (std::size_t j = 0; j < cos_d.size(); ++j) {
      const double a = cos_h[i] * cos_d[j], b = sin_h[i] * sin_d[j];
      for (std::size_t k = 0; k < cos_phi.size(); ++k) {
        const double bk = b * cos_phi[k];
        *out++ = std::max(0.0, a - bk) * std::max(0.0, a + bk);
      }
    }
  return c;
}

std::size_t bin_of(const MerlDims& dims, const Vec3& wi, const Vec3& wo) {
  const HalfDiffAngles a = to_half_diff(wi, wo);
  return dims.flat(theta_h_index(a.theta_h, dims.theta_h), theta_d_index(a.theta_d, dims.theta_d),
                   phi_d_index(a.phi_d, dims.phi_d));
}

TrilinearBins trilinear_bins(const MerlDims& dims, const Vec3& wi, const Vec3& wo) {
  const HalfDiffAngles a = to_half_diff(wi, wo);
  // Coordinates relative to bin centres: bin i's centre sits at u = i.
  const double u = std::clamp(theta_h_coordinate(a.theta_h, dims.theta_h) - 0.5, 0.0, dims.theta_h - 1.0);
  const double v = std::clamp(theta_d_coordinate(a.theta_d, dims.theta_d) - 0.5, 0.0, dims.theta_d - 1.0);
  double w = phi_d_coordinate(a.phi_d, dims.phi_d) - 0.5;
  if (w < 0.0) w += dims.phi_d;
  const int i0 = std::min(static_cast<int>(u), dims.theta_h - 1), i1 = std::min(i0 + 1, dims.theta_h - 1);
  const int j0 = std::min(static_cast<int>(v), dims.theta_d - 1), j1 = std::min(j0 + 1, dims.theta_d - 1);
  const int k0 = std::min(static_cast<int>(w), dims.phi_d - 1), k1 = (k0 + 1) % dims.phi_d;
  const double fu = u - i0, fv = v - j0, fw = w - k0;
  TrilinearBins t;
  for (int corner = 0; corner < 8; ++corner) {
    t.weights[static_cast<std::size_t>(corner)] =
        ((corner & 1) ? fu : 1 - fu) * ((corner & 2) ? fv : 1 - fv) * ((corner & 4) ? fw : 1 - fw);
    t.bins[static_cast<std::size_t>(corner)] =
        dims.flat((corner & 1) ? i1 : i0, (corner & 2) ? j1 : j0, (corner & 4) ? k1 : k0);
  }
  return t;
}

}  // namespace matlas
