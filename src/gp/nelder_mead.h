#pragma once
// Nelder-Mead: the derivative-free minimiser of the small, non-smooth searches in latent space
// (the projection of a material measured in a Gram, eval/latent_fit.h; the fit of sparse samples,
// acquisition/sparse_fit.h), where the objective goes through the convex projection of the
// weights and has kinks. The latent optimisation itself uses L-BFGS and Hooke-Jeeves (optimize.h).
#include <functional>

#include <Eigen/Core>

namespace matlas::gp {

/// Minimises f over R^d by Nelder-Mead from x0 with initial simplex size `step` (reflection 1,
/// expansion 2, contraction 1/2, shrink 1/2); stops after max_evaluations or when the simplex's
/// values agree to `tolerance` (relative) and its extent is below 1e-9 of |x|. Returns the best
/// point seen. Deterministic.
Eigen::VectorXd nelder_mead(const std::function<double(const Eigen::VectorXd&)>& f,
                            Eigen::VectorXd x0, double step, int max_evaluations,
                            double tolerance = 1e-10);

}  // namespace matlas::gp
