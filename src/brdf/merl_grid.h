#pragma once
// The MERL half/difference-angle grid (Matusik et al. 2003; Rusinkiewicz 1998 coordinates).
//
// A bin is addressed by (i, j, k) = (theta_h, theta_d, phi_d) indices. theta_h is sampled
// non-linearly, i = floor(sqrt(theta_h / (pi/2)) * N_h), so that the specular peak gets more bins;
// theta_d and phi_d are uniform over [0, pi/2) and [0, pi). phi_d is folded into [0, pi) by
// reciprocity (f is unchanged under phi_d -> phi_d + pi). The flat index is
// (i * N_d + j) * N_phi + k, as in MERL's reference reader.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "brdf/types.h"

namespace matlas {

/// Grid resolution. The MERL standard (and the only size written for other tools) is 90 90 180.
struct MerlDims {
  int theta_h = 90;
  int theta_d = 90;
  int phi_d = 180;

  std::size_t bins() const {
    return static_cast<std::size_t>(theta_h) * static_cast<std::size_t>(theta_d) *
           static_cast<std::size_t>(phi_d);
  }
  bool is_standard() const { return theta_h == 90 && theta_d == 90 && phi_d == 180; }
  std::size_t flat(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * static_cast<std::size_t>(theta_d) +
            static_cast<std::size_t>(j)) * static_cast<std::size_t>(phi_d) +
           static_cast<std::size_t>(k);
  }
  std::string to_string() const;
  bool operator==(const MerlDims&) const = default;
};

/// Rusinkiewicz half/difference angles of a direction pair.
struct HalfDiffAngles {
  double theta_h = 0, phi_h = 0, theta_d = 0, phi_d = 0;
};

/// (wi, wo) in a local frame (normal +z, unit vectors) -> half/difference angles. phi_d is in
/// (-pi, pi], as atan2 gives it; bin lookups fold it.
HalfDiffAngles to_half_diff(const Vec3& wi, const Vec3& wo);

/// Inverse of to_half_diff: the direction pair (wi, wo) with the given angles.
struct DirectionPair {
  Vec3 wi, wo;
};
DirectionPair from_half_diff(const HalfDiffAngles& a);

/// Reference index mappings (MERL's BRDFRead.cpp), clamped into range.
int theta_h_index(double theta_h, int n_theta_h);
int theta_d_index(double theta_d, int n_theta_d);
int phi_d_index(double phi_d, int n_phi_d);

/// Continuous bin coordinates: bin i covers [i, i+1), its centre is at i + 0.5 (not clamped).
double theta_h_coordinate(double theta_h, int n_theta_h);
double theta_d_coordinate(double theta_d, int n_theta_d);
/// phi_d folded into [0, pi) first.
double phi_d_coordinate(double phi_d, int n_phi_d);

/// Angles at bin centres (the inverse of the coordinates at i + 0.5).
double theta_h_centre(int i, int n_theta_h);
double theta_d_centre(int j, int n_theta_d);
double phi_d_centre(int k, int n_phi_d);
/// The half/difference angles at the centre of bin (i, j, k), with phi_h = 0.
HalfDiffAngles bin_centre(const MerlDims& dims, int i, int j, int k);

/// cos(theta_i) cos(theta_o) at each bin centre (0 below the horizon), by flat bin index: the
/// cosine weighting of perceptual metrics and layout transforms.
std::vector<double> bin_cosine_factors(const MerlDims& dims);

/// The bin holding (wi, wo), as the flat index of MerlDims::flat.
std::size_t bin_of(const MerlDims& dims, const Vec3& wi, const Vec3& wo);

/// The eight bins around (wi, wo) and their trilinear weights between bin centres (theta_h in its
/// square-root coordinate, phi_d periodic with period pi, clamped at the theta edges): what
/// BrdfTable::lookup_smooth and a shader's 3D texture read.
struct TrilinearBins {
  std::array<std::size_t, 8> bins{};
  std::array<double, 8> weights{};
};
TrilinearBins trilinear_bins(const MerlDims& dims, const Vec3& wi, const Vec3& wo);

}  // namespace matlas
