#include "pathtrace/tracer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>

#include "core/check.h"
#include "core/error.h"
#include "core/parallel.h"
#include "pathtrace/mirrored_environment.h"
#include "render/adaptive_sampling.h"
#include "render/sampling.h"

namespace matlas::pathtrace {

namespace {

constexpr int kDrawsPerVertex = 9;  // fixed, so that every path uses the same numbers for every material

double power_heuristic(double a, double b) {
  MATLAS_DCHECK(a >= 0 && b >= 0, "densities");
  const double a2 = a * a, b2 = b * b;
  return a2 + b2 > 0 ? a2 / (a2 + b2) : 0.0;
}

double epsilon_at(const Vec3& p) { return 1e-4 * (1.0 + p.cwiseAbs().maxCoeff()); }

/// Per-pixel sums: P, and N z_k and I2_k for the K materials.
struct Accumulator {
  explicit Accumulator(int k) : once(3 * static_cast<std::size_t>(k)), more(once.size()) {}
  void clear() {
    p = Rgb::Zero();
    std::fill(once.begin(), once.end(), 0.0);
    std::fill(more.begin(), more.end(), 0.0);
  }
  /// A contribution C * prod_j f(bin_j) over `touches` vertices on the object; `factor` holds that
  /// product per material (3K values) when touches > 0.
  void add(const Rgb& c, int touches, const double* factor) {
    if (touches == 0) {
      p += c;
      return;
    }
    std::vector<double>& out = touches == 1 ? once : more;
    MATLAS_DCHECK(factor != nullptr || out.empty(), "a product of measured evaluations");
    for (std::size_t i = 0; i < out.size(); i += 3)
      for (std::size_t ch = 0; ch < 3; ++ch) out[i + ch] += c[static_cast<Eigen::Index>(ch)] * factor[i + ch];
  }
  Rgb p = Rgb::Zero();
  std::vector<double> once, more;
};

struct Frame {
  explicit Frame(const Vec3& normal) : n(normal) { render::orthonormal_basis(n, t, b); }
  Vec3 to_local(const Vec3& v) const { return {v.dot(t), v.dot(b), v.dot(n)}; }
  Vec3 to_world(const Vec3& v) const { return v.x() * t + v.y() * b + v.z() * n; }
  Vec3 n, t, b;
};

class PathTracer {
public:
  PathTracer(const World& world, const render::MaterialBank* bank, const TraceSettings& settings)
      : world_(world), bank_(bank), s_(settings), mirrors_(world, settings.mirror_probability) {}

  /// One camera path through pixel position (px, py), its contributions added to `acc`.
  /// Long (about 120 lines) by choice: one loop iteration is one path vertex, and its emission,
  /// next-event estimation (environment, area lights, directional lights) and continuation share
  /// the vertex's frame, throughput and product of measured evaluations; split into functions they
  /// would pass that state back and forth on every call (pbrt-v4's PathIntegrator::Li is one
  /// function for the same reason).
  void trace_sample(render::SampleStream& rng, double px, double py, Accumulator& acc,
                    std::vector<double>& prod, std::vector<double>& scratch) const {
    Vec3 origin, dir;
    world_.camera_ray(px, py, s_.width, s_.height, &origin, &dir);
    Rgb beta = Rgb::Ones();
    int touches = 0;
    double prev_pdf = 0;
    for (int depth = 0;; ++depth) {
      double u[kDrawsPerVertex];
      for (double& x : u) x = rng.next();
      const auto hit = world_.intersect(origin, dir);
      if (!hit) {
        // An invisible environment lights the scene but camera rays that escape see black.
        if (world_.has_environment() && (depth > 0 || world_.spec().environment.visible)) {
          const render::Environment& env = world_.environment();
          const Rgb le = depth == 0 ? env.eval_smooth(dir) : env.eval(dir);
          const double w = depth == 0 ? 1.0 : power_heuristic(prev_pdf, env.pdf(dir));
          acc.add(beta * le * w, touches, prod.data());
        }
        return;
      }
      MATLAS_DCHECK(hit->object >= 0 && static_cast<std::size_t>(hit->object) < world_.spec().objects.size(),
                    "a hit names one of the scene's objects");
      const ObjectSpec& obj = world_.object(hit->object);
      if (obj.emission.maxCoeff() > 0) {  // area lights emit from their front and reflect nothing
        if (hit->front) {
          double w = 1.0;
          if (depth > 0) {
            const double d2 = (hit->position - origin).squaredNorm();
            const double cos_l = std::abs(hit->geometric_normal.dot(dir));
            w = power_heuristic(prev_pdf, world_.light_pdf_area() * d2 / std::max(cos_l, 1e-12));
          }
          acc.add(beta * obj.emission * w, touches, prod.data());
        }
        return;
      }
      if (depth >= s_.max_depth) return;
      const bool measured = obj.surface.kind == SurfaceSpec::Kind::measured;
      if (measured && !bank_) return;
      const Frame frame(hit->normal);
      const Vec3 wo = frame.to_local(-dir);
      if (wo.z() <= 0) return;
      const Vec3& ng = hit->geometric_normal;
      const Vec3 p = hit->position + epsilon_at(hit->position) * ng;

      // A light contribution arriving from wi (world) with weight c: the path's throughput beta
      // times the light's part (everything but f at this vertex).
      const auto connect = [&](const Vec3& wi_world, const Rgb& c) {
        const Vec3 wi = frame.to_local(wi_world);
        if (measured) {
          MATLAS_DCHECK_EQ(scratch.size(), 3 * static_cast<std::size_t>(bank_->count()));
          bank_->eval_all(wi, wo, scratch.data());
          if (touches > 0)
            for (std::size_t i = 0; i < scratch.size(); ++i) scratch[i] *= prod[i];
          acc.add(c, touches + 1, scratch.data());
        } else {
          acc.add(c * surface_eval(obj.surface, wi, wo), touches, prod.data());
        }
      };
      // The density of the vertex's next direction (local): its own, mixed with the environment's
      // mirror images when it sees a glossy plane.
      const double mirrored = mirrors_.probability(hit->object);
      const auto mixed = [&](double own, const Vec3& wi) {
        return mirrored > 0 ? (1.0 - mirrored) * own + mirrored * mirrors_.pdf(hit->object, frame.to_world(wi)) : own;
      };
      const auto bsdf_pdf = [&](const Vec3& wi) {
        return mixed(measured ? s_.density.pdf(wo, wi) : surface_pdf(obj.surface, wo, wi), wi);
      };

      // Next-event estimation: the environment.
      if (world_.has_environment()) {
        double pdf_e = 0;
        const Vec3 wl = world_.environment().sample(u[0], u[1], &pdf_e);
        const double cos_i = frame.to_local(wl).z();
        if (pdf_e > 0 && cos_i > 0 && wl.dot(ng) > 0 && !world_.occluded(p, wl, 0.0, 1e30)) {
          const double w = power_heuristic(pdf_e, bsdf_pdf(frame.to_local(wl)));
          connect(wl, beta * world_.environment().eval(wl) * (cos_i * w / pdf_e));
        }
      }
      // Next-event estimation: the area lights.
      if (world_.has_lights()) {
        const LightSample l = world_.sample_light(u[2], u[3], u[4]);
        const Vec3 to = l.position - p;
        const double dist = to.norm();
        const Vec3 wl = to / dist;
        const double cos_l = -wl.dot(l.normal), cos_i = frame.to_local(wl).z();
        if (cos_l > 0 && cos_i > 0 && wl.dot(ng) > 0 && !world_.occluded(p, wl, 0.0, dist * (1.0 - 1e-4))) {
          const double pdf_l = l.pdf_area * dist * dist / cos_l;
          const double w = power_heuristic(pdf_l, bsdf_pdf(frame.to_local(wl)));
          connect(wl, beta * l.emission * (cos_i * w / pdf_l));
        }
      }
      // Next-event estimation: every directional light (delta lights: no surface sample reaches
      // them, so no MIS weight; no random numbers).
      for (const render::DirectionalLight& l : world_.directional_lights()) {
        const double cos_i = frame.to_local(l.direction).z();
        if (cos_i > 0 && l.direction.dot(ng) > 0 && !world_.occluded(p, l.direction, 0.0, 1e30))
          connect(l.direction, beta * l.irradiance * cos_i);
      }

      // Continue the path.
      Vec3 wi;
      double pdf = 0;
      if (u[5] < mirrored) {
        wi = frame.to_local(mirrors_.sample(hit->object, u[5] / mirrored, u[6], u[7]));
        if (wi.z() <= 0) return;
        pdf = bsdf_pdf(wi);
      } else {
        const double v = (u[5] - mirrored) / (1.0 - mirrored);
        pdf = measured ? s_.density.sample(wo, v, u[6], u[7], &wi) : surface_sample(obj.surface, wo, v, u[6], u[7], &wi);
        MATLAS_DCHECK(!(pdf < 0), "a sampling density");
        if (pdf > 0) pdf = mixed(pdf, wi);  // (the draw's own density is its pdf(): not evaluated twice)
      }
      if (!(pdf > 0)) return;
      const Vec3 wi_world = frame.to_world(wi);
      if (wi_world.dot(ng) <= 0) return;
      if (measured) {
        beta *= wi.z() / pdf;
        bank_->eval_all(wi, wo, scratch.data());
        if (touches == 0) prod = scratch;
        else
          for (std::size_t i = 0; i < prod.size(); ++i) prod[i] *= scratch[i];
        ++touches;
      } else {
        beta *= surface_eval(obj.surface, wi, wo) * (wi.z() / pdf);
      }
      origin = p;
      dir = wi_world;
      prev_pdf = pdf;
      // Russian roulette on the material-independent weight (an object vertex counts as 0.5).
      if (depth + 1 >= s_.roulette_depth) {
        const double q = std::clamp(beta.maxCoeff() * std::pow(0.5, touches), 0.05, 0.95);
        if (u[8] >= q) return;
        beta /= q;
      }
    }
  }

  const World& world_;
  const render::MaterialBank* bank_;
  const TraceSettings& s_;
  const MirroredEnvironment mirrors_;
};

}  // namespace

void TraceSettings::validate() const {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) throw Error("image size must be in 1..16384");
  if (spp <= 0) throw Error("spp must be positive");
  if (max_depth <= 0 || max_depth > 64) throw Error("max depth must be in 1..64");
  if (roulette_depth < 1) throw Error("roulette depth must be positive");
  density.validate();
  if (!(mirror_probability >= 0 && mirror_probability < 1)) throw Error("the mirror probability must be in [0, 1)");
  if (density.environment != 0)
    throw Error("the path tracer samples the environment by next-event estimation: its density's environment probability must be 0");
  render::check_pixel_samples(pixel_samples.get(), width, height);
}

Image TraceImages::i1(int k) const {
  MATLAS_CHECK(k >= 0 && static_cast<std::size_t>(k) < once.size(), "material index in range");
  Image out = p;
  const Image& n = once[static_cast<std::size_t>(k)];
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += n.rgb[i];
  return out;
}

Image TraceImages::full(int k) const {
  Image out = i1(k);
  MATLAS_CHECK_EQ(more.size(), once.size());
  const Image& m = more[static_cast<std::size_t>(k)];
  for (std::size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += m.rgb[i];
  return out;
}

TraceImages trace(const World& world, const render::MaterialBank* bank, const TraceSettings& settings, ProgressSink& progress) {
  settings.validate();
  if (world.measured_object() >= 0 && bank && !(bank->count() > 0)) throw Error("the material bank is empty");
  const int k = (bank && world.measured_object() >= 0) ? bank->count() : 0;
  const render::MaterialBank* used = k > 0 ? bank : nullptr;
  TraceImages out;
  out.p = Image(settings.width, settings.height);
  out.once.assign(static_cast<std::size_t>(k), Image(settings.width, settings.height));
  out.more.assign(static_cast<std::size_t>(k), Image(settings.width, settings.height));
  MATLAS_CHECK(used == nullptr || used->count() == k, "the accumulators hold a value per material of the bank");
  const PathTracer tracer(world, used, settings);
  std::atomic<std::uint64_t> rows_done{0};
  std::mutex progress_mutex;
  parallel_for_each(0, static_cast<std::size_t>(settings.height), [&](std::size_t row) {
    const int y = static_cast<int>(row);
    Accumulator acc(k);
    std::vector<double> prod(3 * static_cast<std::size_t>(k)), scratch(prod.size());
    for (int x = 0; x < settings.width; ++x) {
      acc.clear();
      const std::uint64_t pixel = static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(settings.width) + static_cast<std::uint64_t>(x);
      const int n = settings.pixel_samples ? render::pixel_sample_count(settings.spp, (*settings.pixel_samples)[pixel])
                                           : settings.spp;
      const double inv = 1.0 / n;
      for (int s = 0; s < n; ++s) {
        render::SampleStream rng(settings.seed, pixel, static_cast<std::uint64_t>(s));
        const double px = x + rng.next(), py = y + rng.next();
        tracer.trace_sample(rng, px, py, acc, prod, scratch);
      }
      float* pp = out.p.pixel(x, y);
      for (int c = 0; c < 3; ++c) pp[c] = static_cast<float>(acc.p[c] * inv);
      for (int m = 0; m < k; ++m) {
        float* po = out.once[static_cast<std::size_t>(m)].pixel(x, y);
        float* pm = out.more[static_cast<std::size_t>(m)].pixel(x, y);
        for (std::size_t c = 0; c < 3; ++c) {
          po[c] = static_cast<float>(acc.once[3 * static_cast<std::size_t>(m) + c] * inv);
          pm[c] = static_cast<float>(acc.more[3 * static_cast<std::size_t>(m) + c] * inv);
        }
      }
    }
    const std::uint64_t done = ++rows_done;
    const std::lock_guard lock(progress_mutex);
    progress.update("path tracing", done, static_cast<std::uint64_t>(settings.height));
  });
  progress.finish("path tracing");
  return out;
}

}  // namespace matlas::pathtrace
