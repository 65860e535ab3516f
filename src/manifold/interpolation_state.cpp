#include "manifold/interpolation_state.h"

#include "gp/posterior.h"
#include "manifold/model.h"

namespace matlas {

InterpolationState interpolation_state(const Model& model) {
  const gp::GpPosterior& gp = model.posterior();
  InterpolationState s;
  s.latent = model.latent();
  s.lengthscale = gp.kernel().lengthscale;
  s.nugget = gp.kernel().nugget;
  s.taper_radius = gp.taper_radius();
  s.cholesky_lower = gp.cholesky().matrixL();
  s.convex_metric = model.convex_metric();
  return s;
}

}  // namespace matlas
