#pragma once
// The data behind the page's panels for one interpolated material m(x), given its weights w(x):
// the theta_h x theta_d image slice, the lobe in the plane of incidence, and the albedo curve.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "brdf/types.h"

namespace matlas {
class Model;
}

namespace matlas::atlas {

/// The theta_h x theta_d slice at one phi_d as an RGB PNG: column i is theta_h bin i (left: 0),
/// row j is theta_d bin j (top: 0). Values are shown as log(1 + f / 0.01) normalised by the
/// slice's largest value (returned in *max_value), then sRGB-encoded.
std::string slice_png(const Model& model, const Eigen::VectorXd& w, double phi_d_degrees,
                      double* max_value = nullptr);

/// f(wi, wo) in the plane of incidence: wi at polar angle theta_i on the -x side, wo swept from
/// -90 to +90 degrees (positive: the mirror side). Nearest-bin lookups through the model.
struct Lobe {
  double theta_i_degrees = 0;
  std::vector<double> theta_o_degrees;
  std::vector<Rgb> value;
};
Lobe incidence_plane_lobe(const Model& model, const Eigen::VectorXd& w, double theta_i_degrees,
                          int samples);

/// theta_o (degrees) of each entry of Model::albedo_curve: bin centres of kAlbedoAngles uniform bins.
std::vector<double> albedo_angles_degrees();

}  // namespace matlas::atlas
