#include "render/directional_light.h"

namespace matlas::render {

std::string light_problem(const DirectionalLight& light, const std::string& name) {
  const Vec3& d = light.direction;
  if (!d.allFinite() || !(d.cwiseAbs().maxCoeff() <= kMaxSceneCoordinate))  // maxCoeff may skip a NaN
    return name + ".direction must be finite, with coordinates within +-1e6";
  if (!(d.norm() >= 1e-6)) return name + ".direction must have a length of 1e-6 at least";
  const Rgb& e = light.irradiance;
  if (!e.allFinite() || !(e.minCoeff() >= 0 && e.maxCoeff() <= kMaxSceneCoordinate))
    return name + ".irradiance must be in [0, 1e6]";
  return {};
}

}  // namespace matlas::render
