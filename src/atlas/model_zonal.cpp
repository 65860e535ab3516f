#include "atlas/model_zonal.h"

#include <cstddef>

namespace matlas::atlas {

zonal::CoefficientSet model_coefficients(const Model& model, const zonal::ProjectionSettings& settings) {
  const zonal::ZonalProjector projector(settings, model.dims());
  zonal::CoefficientSet set;
  set.settings = settings;
  set.names = model.names();
  set.materials.resize(static_cast<std::size_t>(model.count()));
  for (int i = 0; i < model.count(); ++i)
    set.materials[static_cast<std::size_t>(i)] = projector.project(model.table(model.material_weights(i)));
  set.mean = projector.project(model.table(Eigen::VectorXd::Zero(model.count())));
  return set;
}

}  // namespace matlas::atlas
