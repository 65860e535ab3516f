#pragma once
// Synthetic RGL `.bsdf` contents (formats/rgl_bsdf.h) for the tests.
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/tensor_file.h"

namespace matlas::test {

/// A small measured BSDF whose evaluation is known in closed form: the VNDF is uniform (its
/// inverse warp is the identity), the NDF is 1 + x and sigma 0.5 + 0.25 x in their unit
/// coordinates, and the reflectance of channel c at incident elevation theta_i is
/// (1 + theta_i) (0.2 + 0.1 c + 0.3 x + 0.1 y + 0.2 x y): all reproduced exactly by bilinear
/// interpolation and by linear interpolation in theta_i.
struct SyntheticRgl {
  std::vector<float> theta_i{0.0f, 0.6f, 1.2f, 1.5707964f};
  std::vector<float> phi_i{0.0f};
  std::size_t vndf_res = 6, refl_res = 5;
  bool jacobian = true;
  /// Multiplies the reflectance (distinct materials for databases).
  double scale = 1.0;
  /// Spectral instead of RGB: `wavelengths` samples, every channel's formula as channel 1's.
  std::vector<float> wavelengths;

  static double reflectance(int c, double theta_i, double x, double y) {
    return (1.0 + theta_i) * (0.2 + 0.1 * c + 0.3 * x + 0.1 * y + 0.2 * x * y);
  }

  std::vector<TensorField> fields() const {
    const std::size_t np = phi_i.size(), nt = theta_i.size();
    std::vector<TensorField> f;
    const std::string text = "synthetic test material";
    f.push_back(uint8_field("description", {text.size()},
                            std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size())));
    f.push_back(float32_field("phi_i", {np}, phi_i));
    f.push_back(float32_field("theta_i", {nt}, theta_i));
    std::vector<float> ndf, sigma;
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x) {
        ndf.push_back(static_cast<float>(1.0 + x / 3.0));
        sigma.push_back(static_cast<float>(0.5 + 0.25 * x / 3.0));
      }
    f.push_back(float32_field("sigma", {2, 4}, sigma));
    f.push_back(float32_field("ndf", {2, 4}, ndf));
    std::vector<float> vndf(np * nt * vndf_res * vndf_res, 1.0f);
    f.push_back(float32_field("vndf", {np, nt, vndf_res, vndf_res}, vndf));
    std::vector<float> lum(np * nt * refl_res * refl_res, 1.0f);
    f.push_back(float32_field("luminance", {np, nt, refl_res, refl_res}, lum));
    const std::size_t channels = wavelengths.empty() ? 3 : wavelengths.size();
    std::vector<float> refl;
    for (std::size_t p = 0; p < np; ++p)
      for (std::size_t t = 0; t < nt; ++t)
        for (std::size_t c = 0; c < channels; ++c)
          for (std::size_t y = 0; y < refl_res; ++y)
            for (std::size_t x = 0; x < refl_res; ++x)
              refl.push_back(static_cast<float>(scale * reflectance(wavelengths.empty() ? static_cast<int>(c) : 1, theta_i[t],
                                                            x / double(refl_res - 1), y / double(refl_res - 1))));
    if (wavelengths.empty()) {
      f.push_back(float32_field("rgb", {np, nt, 3, refl_res, refl_res}, refl));
    } else {
      f.push_back(float32_field("wavelengths", {channels}, wavelengths));
      f.push_back(float32_field("spectra", {np, nt, channels, refl_res, refl_res}, refl));
    }
    const std::uint8_t jac[1] = {static_cast<std::uint8_t>(jacobian ? 1 : 0)};
    f.push_back(uint8_field("jacobian", {1}, jac));
    return f;
  }
};

}  // namespace matlas::test
