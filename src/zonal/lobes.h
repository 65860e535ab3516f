#pragma once
// Sharp lobes beside the rotated-ZH expansion (docs/REALTIME.md, "Sharp lobes").
//
// A truncated expansion cannot hold a glossy slice's peak around the mirror direction: it rings
// and blurs. The slice rho_theta_o(w) (0 below the horizon) is therefore written as
//
//     rho ~ sum_i c_i(theta_o) Kc_i(w) + P_L[rho - sum_i c_i Kc_i],   Kc_i(w) = K_i(r . w) max(w_z, 0),
//
// r = (-sin theta_o, 0, cos theta_o) the mirror direction of wo, K_i(t) = N(kappa_i)
// exp(kappa_i (t - 1)) a normalised von Mises-Fisher lobe (integral 1 over the sphere) of fixed
// sharpness kappa_i, times the cosine as the slice is (so the lobe vanishes at the horizon as the
// slice does, and the remainder has no edge there to ring), P_L the projection onto bands 0..L
// (the ZH part). The c_i minimise the error of that representation, ||(1 - P_L)(rho - sum_i c_i
// Kc_i)||^2 over the upper hemisphere, with c_i >= 0: what the lobes must carry is the part of rho
// above band L, and a lobe is a peak, never a hole (an unconstrained fit gives mirror-like
// materials lobes of negative weight whose dips only the expansion's finest bands cancel; any
// window over the bands then shows them as dark holes in the highlight, and without a window the
// cancelling bands ring over the whole object: docs/REALTIME.md, "Sharp lobes"). The fit is a
// small quadratic programme with a Gram matrix fixed per theta_o (nonnegative_minimiser). Where the
// unconstrained weights are all positive it is linear in rho; a map point's coefficients are the
// same weighted sum of the materials' stored ones in every case. Shading adds
// sum_i c_i(theta_o) mass_i(theta_o) E_i(R r), E_i the environment convolved with K_i and
// mass_i the integral of Kc_i (the environment taken as even over the lobe; the stored weight is
// c_i mass_i): one lookup per lobe, split-sum style (a map per sharpness, the weights per material).
//
// Zonal expansion of a lobe: K(r . w) = sum_l k_l sum_m Y_l^m(r) Y_l^m(w), k_l = 2 pi
// integral_{-1}^{1} K(t) P_l(t) dt (Funk-Hecke; k_0 = 1, k_l ~ exp(-l (l + 1) / (2 kappa))).
#include <vector>

#include <Eigen/Core>

#include "brdf/types.h"

namespace matlas::zonal {

/// The sharpnesses used by the viewer and `matlas zonal` unless told otherwise: lobes of
/// about 7, 3.6, 1.8 and 0.9 degrees (1 / sqrt(kappa) radians).
inline const std::vector<double> kDefaultLobes = {64.0, 256.0, 1024.0, 4096.0};

/// N(kappa) = kappa / (2 pi (1 - exp(-2 kappa))).
double lobe_normalisation(double kappa);
/// K(t) = N exp(kappa (t - 1)).
double lobe_value(double kappa, double t);
/// k_0..k_L of the lobe (composite Simpson in u = kappa (1 - t); k_0 = 1 to 1e-9).
std::vector<double> lobe_legendre(double kappa, int L);
/// integral over the sphere of K_a(r . w) K_b(r . w) (same axis): N_a N_b 2 pi (1 - e^{-2(a+b)}) / (a + b).
double lobe_product(double a, double b);
/// integral over the sphere of K(r . w) max(w_z, 0), r_z = cos of the lobe axis' angle to the
/// normal: the cosine-weighted lobe's mass (-> r_z for a sharp lobe above the horizon).
double lobe_cosine_mass(double kappa, double rz);
/// argmin over c >= 0 of 1/2 c^T G c - c^T r, G symmetric positive definite, M x M with M <= 8
/// (the lobes' count). Exact: the unconstrained minimiser if it is non-negative, else the best
/// of the minimisers on every support that are non-negative (the optimum is one of them).
Eigen::VectorXd nonnegative_minimiser(const Eigen::MatrixXd& G, const Eigen::VectorXd& r);
/// Throws matlas::Error unless every kappa is in [1, 65536] and they are strictly increasing.
void validate_lobes(const std::vector<double>& kappas);

}  // namespace matlas::zonal
