#pragma once
// The data of the browser's real-time viewer (docs/API.md "Real-time viewer", docs/REALTIME.md):
// the rotated-ZH coefficients of every input material and of the model's mean (on first use: read
// from the cache beside the model, MODEL.zonal-L16, or computed and cached; then kept), the per-band prefiltered maps of an environment
// (computed once per environment and kept), the installed meshes as files, and the CPU reference
// image of a map point (zonal::shade_image of the sphere, the test's ground truth). HTTP-free: the
// Api wraps the results into replies.
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "formats/image_io.h"
#include "atlas/model_light_tables.h"
#include "zonal/coefficient_file.h"
#include "zonal/light_split.h"
#include "zonal/prefilter.h"
#include "zonal/window.h"

namespace matlas {
class Model;
}

namespace matlas::server {

/// L and T of the viewer: L = 16 (153 coefficients, docs/REALTIME.md's preview setting), T = 32.
inline constexpr int kRealtimeBands = 16;
inline constexpr int kRealtimeThetaO = 32;
/// The windows over the bands shown (zonal/window.h, zonal::ShadeSettings), in the shader and the
/// reference alike. With every band: none, because the coefficients carry a window per theta_o
/// sample chosen from themselves (zonal/ring_limit.h, floor kRealtimeRingFloor): the plain
/// truncation where it does not ring, towards Hann where it would (the rim of glossy materials
/// under small bright lights). docs/REALTIME.md "Accuracy of the viewer" measures it against
/// Hann over every band and no window. With fewer bands (the bands slider, the
/// reduced frames while moving): Hann. The page holds the same two names
/// (web/src/realtime-shader.ts: viewerWindow, viewerReducedWindow).
inline constexpr zonal::BandWindow kRealtimeWindow = zonal::BandWindow::none;
inline constexpr zonal::BandWindow kRealtimeReducedWindow = zonal::BandWindow::hann;
inline constexpr double kRealtimeRingFloor = 0.05;
/// The direct lights (zonal/light_split.h): an environment's 512 brightest texels (at least 8 times
/// its mean luminance), one point each, shaded with the map point's light table
/// (zonal/light_table.h); the band and lobe maps hold the rest. docs/REALTIME.md "Direct lights".
inline constexpr zonal::LightSplitSettings kRealtimeLights{512, 8.0, 1};

class Realtime {
public:
  /// `environments`: the names offered (installed maps, or "constant").
  Realtime(const Model& model, std::vector<std::string> environments, std::vector<std::string> objects);

  /// Shapes and the basis: bands, theta_o, alpha, band, materials, environments, objects, the
  /// reference camera, how long the coefficients took and whether they came from the cache.
  nlohmann::json info();
  /// float32 little-endian: the mean's [T, K, 3], then each material's (zonal/shader_layout.h).
  const std::string& coefficients();
  /// {"bands", "width", "height", "detail", "lights"} and the float32 [L + 1, H, W, 3] atlas of
  /// `name` (the band maps of the environment without its lights), followed by the detail atlas
  /// (zonal::pack_detail: the lobe maps, then the whole environment as the background) at
  /// detail.offset floats, [detail.layers, detail.height, detail.width, 3], then the lights at
  /// lights.offset floats, [lights.count][6]: unit direction (unrotated map), radiance x solid angle.
  std::pair<nlohmann::json, std::shared_ptr<const std::string>> environment(const std::string& name);
  /// An offered mesh ("bunny", "suzi") as the renderer places it (render::place_object):
  /// uint32 vertex and triangle counts, float32 positions [v][3], normals [v][3], uint32 [t][3].
  std::string mesh(const std::string& name) const;
  /// The light table of the point with weights w (atlas::ModelLightTables, built on first use):
  /// float16 little-endian [theta_h][theta_d][phi_d][3] on light_table_dims().
  std::string light_table(const Eigen::VectorXd& w);
  /// RGBA PNG: the sphere of the reference camera with weights w under `env` (rotated by
  /// `rotation` degrees about +y), shaded by zonal::shade_image, tone mapped (clamp, exposure in
  /// stops, sRGB); alpha 255 where the sphere covers the whole pixel, 0 elsewhere.
  std::string reference_png(const Eigen::VectorXd& w, const std::string& env, double rotation, double exposure,
                            int size);
  /// The same image before tone mapping: float32 RGBA, row-major from the top, RGB = 2^exposure
  /// times the radiance (not clamped), A = the fraction of the pixel the sphere covers.
  std::string reference_radiance(const Eigen::VectorXd& w, const std::string& env, double rotation, double exposure,
                                 int size);

private:
  struct Reference {
    Image image;                ///< radiance, RGB
    std::vector<float> coverage;  ///< per pixel
  };
  Reference reference(const Eigen::VectorXd& w, const std::string& env, double rotation, int size);
  struct Prefiltered {
    std::shared_ptr<const zonal::PrefilteredEnvironment> maps;
    std::shared_ptr<const std::string> atlas;
    nlohmann::json shape;
    std::vector<zonal::LightPoint> lights;  ///< the unrotated map's
  };
  const zonal::CoefficientSet& set();
  const atlas::ModelLightTables& light_tables();
  const Prefiltered& prefiltered(const std::string& name);

  const Model& model_;
  std::vector<std::string> envs_, objects_;
  std::mutex coefficients_mutex_, env_mutex_, lights_mutex_;
  std::unique_ptr<atlas::ModelLightTables> light_tables_;
  std::unique_ptr<zonal::CoefficientSet> set_;
  std::string packed_;
  double seconds_ = 0;
  std::string cache_, cache_note_;  ///< "loaded"/"computed" and what happened (atlas/zonal_cache.h)
  std::map<std::string, Prefiltered> envs_cache_;
};

}  // namespace matlas::server
