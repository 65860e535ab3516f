#include "pathtrace/mirrored_environment.h"

#include <algorithm>

#include "core/check.h"

namespace matlas::pathtrace {

MirroredEnvironment::MirroredEnvironment(const World& world, double probability)
    : world_(world), probability_(probability) {
  MATLAS_CHECK(probability >= 0 && probability < 1, "a mixture probability in [0, 1)");
  if (!world.has_environment() || probability == 0) return;
  const std::vector<ObjectSpec>& objects = world.spec().objects;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const ObjectSpec& o = objects[i];
    const SurfaceSpec& s = o.surface;
    if (o.shape != "quad" || o.emission.maxCoeff() > 0 || s.kind != SurfaceSpec::Kind::ggx) continue;
    if (!(s.specular.maxCoeff() > 0) || s.alpha > kMirrorPlaneMaxAlpha) continue;
    const Vec3 n = o.edge1.cross(o.edge2);
    if (!(n.norm() > 0)) continue;
    planes_.push_back({static_cast<int>(i), n.normalized()});
  }
}

int MirroredEnvironment::usable(int object) const {
  int count = 0;
  for (const Plane& p : planes_) count += p.object != object;
  return count;
}

double MirroredEnvironment::probability(int object) const {
  return usable(object) > 0 ? probability_ : 0.0;
}

Vec3 MirroredEnvironment::sample(int object, double u_plane, double u0, double u1) const {
  const int count = usable(object);
  MATLAS_CHECK_GT(count, 0);
  int pick = std::min(count - 1, static_cast<int>(u_plane * count));
  const Plane* chosen = nullptr;
  for (const Plane& p : planes_)
    if (p.object != object && pick-- == 0) {
      chosen = &p;
      break;
    }
  MATLAS_CHECK(chosen != nullptr, "a usable plane was picked");
  double pdf_env = 0;
  return mirror(world_.environment().sample(u0, u1, &pdf_env), chosen->normal);
}

double MirroredEnvironment::pdf(int object, const Vec3& w) const {
  const int count = usable(object);
  if (count == 0) return 0.0;
  double sum = 0;
  for (const Plane& p : planes_)
    if (p.object != object) sum += world_.environment().pdf(mirror(w, p.normal));
  return sum / count;
}

}  // namespace matlas::pathtrace
