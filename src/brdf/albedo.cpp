#include "brdf/albedo.h"

#include <algorithm>
#include <array>
#include <string>

#include "core/error.h"
#include "core/parallel.h"

namespace matlas {

std::vector<Vec3> cosine_quadrature(int resolution) {
  std::vector<Vec3> dirs;
  dirs.reserve(static_cast<std::size_t>(resolution) * static_cast<std::size_t>(resolution));
  for (int a = 0; a < resolution; ++a) {
    const double u = (a + 0.5) / resolution;
    const double r = std::sqrt(u);
    const double z = std::sqrt(std::max(0.0, 1.0 - u));
    for (int b = 0; b < resolution; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / resolution;
      dirs.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  }
  return dirs;
}

namespace {

/// Gauss-Legendre points and weights on [0, 1].
struct GaussRule {
  std::array<double, 4> x{}, w{};
  int count = 0;
};

GaussRule gauss_legendre(int points) {
  GaussRule g;
  g.count = points;
  // Nodes t and weights on [-1, 1]; mapped by x = (1 + t) / 2, w / 2.
  auto set = [&](std::initializer_list<double> t, std::initializer_list<double> w) {
    int k = 0;
    for (auto it_t = t.begin(), it_w = w.begin(); it_t != t.end(); ++it_t, ++it_w, ++k) {
      g.x[static_cast<std::size_t>(k)] = 0.5 * (1.0 + *it_t);
      g.w[static_cast<std::size_t>(k)] = 0.5 * *it_w;
    }
  };
  switch (points) {
    case 1: set({0.0}, {2.0}); break;
    case 2: set({-0.57735026918962576, 0.57735026918962576}, {1.0, 1.0}); break;
    case 3: set({-0.77459666924148338, 0.0, 0.77459666924148338}, {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0}); break;
    case 4:
      set({-0.86113631159405258, -0.33998104358485626, 0.33998104358485626, 0.86113631159405258},
          {0.34785484513745386, 0.65214515486254614, 0.65214515486254614, 0.34785484513745386});
      break;
    default: throw Error("albedo quadrature: theta_h_points must be 1 to 4, got " + std::to_string(points));
  }
  return g;
}

}  // namespace

std::vector<AlbedoTerm> albedo_rule(const MerlDims& dims, double theta_o, const AlbedoQuadrature& q) {
  const GaussRule g = gauss_legendre(q.theta_h_points);
  if (q.phi_h_points < 1) throw Error("albedo quadrature: phi_h_points must be positive");
  const Vec3 wo = direction_at_theta(theta_o);
  const int nh = dims.theta_h, nphi = q.phi_h_points;
  const double dphi = 2.0 * kPi / nphi;
  std::vector<double> cos_phi(static_cast<std::size_t>(nphi)), sin_phi(cos_phi.size());
  for (int b = 0; b < nphi; ++b) {
    cos_phi[static_cast<std::size_t>(b)] = std::cos((b + 0.5) * dphi);
    sin_phi[static_cast<std::size_t>(b)] = std::sin((b + 0.5) * dphi);
  }
  std::vector<AlbedoTerm> terms;
  terms.reserve(static_cast<std::size_t>(nh) * static_cast<std::size_t>(g.count) * cos_phi.size());
  for (int i = 0; i < nh; ++i)
    for (int p = 0; p < g.count; ++p) {
      // theta_h = u^2 pi/2: dtheta_h = pi u du; dw_h = sin(theta_h) dtheta_h dphi_h.
      const double u = (i + g.x[static_cast<std::size_t>(p)]) / nh;
      const double theta_h = u * u * (kPi / 2.0);
      const double ct = std::cos(theta_h), st = std::sin(theta_h);
      const double measure = kPi * u * st * (g.w[static_cast<std::size_t>(p)] / nh) * dphi;
      for (std::size_t b = 0; b < cos_phi.size(); ++b) {
        const Vec3 h(st * cos_phi[b], st * sin_phi[b], ct);
        const double o_h = wo.dot(h);
        if (o_h <= 0.0) continue;
        const Vec3 wi = 2.0 * o_h * h - wo;
        if (wi.z() <= 0.0) continue;
        // Difference angles as to_half_diff computes them: wi in the frame of h (rotated by
        // -phi_h about z, then -theta_h about y); the angle between wi and h is that of wo and h.
        const double tx = cos_phi[b] * wi.x() + sin_phi[b] * wi.y();
        const double ty = -sin_phi[b] * wi.x() + cos_phi[b] * wi.y();
        const double dx = ct * tx - st * wi.z();
        const int j = theta_d_index(std::acos(std::min(1.0, o_h)), dims.theta_d);
        const double weight = 4.0 * o_h * wi.z() * measure;
        if (std::abs(ty) > 1e-12) {
          terms.push_back({dims.flat(i, j, phi_d_index(std::atan2(ty, dx), dims.phi_d)), weight});
        } else {
          // wi, wo, h and the normal in one plane (every point at normal incidence): phi_d is 0
          // or pi, the first or the last bin, as rounding decides. Half to each, the limit of
          // theta_o -> 0 (where half the azimuths fall on either side).
          terms.push_back({dims.flat(i, j, 0), 0.5 * weight});
          terms.push_back({dims.flat(i, j, dims.phi_d - 1), 0.5 * weight});
        }
      }
    }
  std::sort(terms.begin(), terms.end(), [](const AlbedoTerm& a, const AlbedoTerm& b) { return a.bin < b.bin; });
  std::size_t out = 0;
  for (std::size_t k = 0; k < terms.size(); ++k) {
    if (out > 0 && terms[out - 1].bin == terms[k].bin)
      terms[out - 1].weight += terms[k].weight;
    else
      terms[out++] = terms[k];
  }
  terms.resize(out);
  return terms;
}

Rgb directional_albedo(const BrdfTable& table, double theta_o, const AlbedoQuadrature& q) {
  Rgb sum = Rgb::Zero();
  for (const AlbedoTerm& t : albedo_rule(table.dims(), theta_o, q)) sum += t.weight * table.bin_rgb(t.bin);
  return sum;
}

std::vector<Rgb> albedo_curve(const BrdfTable& table, int count, const AlbedoQuadrature& q) {
  std::vector<Rgb> curve(static_cast<std::size_t>(count));
  parallel_for(0, curve.size(), [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i)
      curve[i] = directional_albedo(table, (static_cast<double>(i) + 0.5) / count * (kPi / 2.0), q);
  });
  return curve;
}

std::string albedo_rule_description(const AlbedoQuadrature& q) {
  return "half-vector quadrature per theta_h bin (dwi = 4 (wo.h) dwh): " + std::to_string(q.theta_h_points) +
         " Gauss-Legendre points in sqrt(theta_h) per bin x " + std::to_string(q.phi_h_points) +
         " azimuths, MERL nearest-bin lookup, missing values as 0";
}

Rgb normal_albedo(const BrdfTable& table, double cone_deg, int rings, const AlbedoQuadrature& q) {
  Rgb sum = Rgb::Zero();
  double weights = 0;
  for (int k = 0; k < rings; ++k) {
    const double theta = (k + 0.5) / rings * cone_deg * kPi / 180.0;
    const double w = std::sin(theta);
    sum += w * directional_albedo(table, theta, q);
    weights += w;
  }
  return sum / weights;
}

}  // namespace matlas
