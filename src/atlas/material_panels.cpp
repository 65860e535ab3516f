#include "atlas/material_panels.h"

#include <algorithm>
#include <cmath>

#include "formats/image_io.h"
#include "manifold/model.h"

namespace matlas::atlas {

std::string slice_png(const Model& model, const Eigen::VectorXd& w, double phi_d_degrees,
                      double* max_value) {
  const MerlDims& dims = model.dims();
  const int k = phi_d_index(phi_d_degrees * kPi / 180.0, dims.phi_d);
  const int width = dims.theta_h, height = dims.theta_d;
  std::vector<Rgb> values(static_cast<std::size_t>(width) * height);
  double vmax = 0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      Rgb v = model.bin_rgb(dims.flat(i, j, k), w).max(0.0);
      values[static_cast<std::size_t>(j) * width + i] = v;
      vmax = std::max(vmax, v.maxCoeff());
    }
  if (max_value) *max_value = vmax;
  constexpr double kScale = 0.01;
  const double norm = std::log1p(std::max(vmax, 1e-9) / kScale);
  std::vector<unsigned char> pixels(values.size() * 3);
  for (std::size_t p = 0; p < values.size(); ++p)
    for (int c = 0; c < 3; ++c) {
      const double t = std::clamp(std::log1p(values[p][c] / kScale) / norm, 0.0, 1.0);
      pixels[p * 3 + static_cast<std::size_t>(c)] =
          static_cast<unsigned char>(std::lround(255.0 * srgb_encode(static_cast<float>(t))));
    }
  return encode_png_srgb8(pixels.data(), width, height);
}

Lobe incidence_plane_lobe(const Model& model, const Eigen::VectorXd& w, double theta_i_degrees,
                          int samples) {
  Lobe lobe;
  lobe.theta_i_degrees = theta_i_degrees;
  const double ti = theta_i_degrees * kPi / 180.0;
  const Vec3 wi(-std::sin(ti), 0.0, std::cos(ti));
  // Sample centres of `samples` equal intervals of (-90, 90): the horizon itself is never hit.
  for (int s = 0; s < samples; ++s) {
    const double deg = -90.0 + 180.0 * (s + 0.5) / samples;
    const double to = deg * kPi / 180.0;
    const Vec3 wo(std::sin(to), 0.0, std::cos(to));
    lobe.theta_o_degrees.push_back(deg);
    lobe.value.push_back(model.lookup(wi.normalized(), wo.normalized(), w).max(0.0));
  }
  return lobe;
}

std::vector<double> albedo_angles_degrees() {
  std::vector<double> a(kAlbedoAngles);
  for (int t = 0; t < kAlbedoAngles; ++t) a[static_cast<std::size_t>(t)] = 90.0 * (t + 0.5) / kAlbedoAngles;
  return a;
}

}  // namespace matlas::atlas
