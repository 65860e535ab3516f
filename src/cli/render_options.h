#pragma once
// Command-line options shared by the rendering commands (render, basis, map, gallery): scene,
// lighting, camera, image size, samples and tone mapping; the path tracer's (render, basis).
#include <filesystem>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "formats/image_io.h"
#include "pathtrace/tracer.h"
#include "render/render.h"
#include "render/scene.h"

namespace matlas {
class Model;
}

namespace matlas::cli {

struct RenderOptions {
  std::string scene = "sphere";
  std::string env = "studio";
  double env_rotation = 0.0, env_intensity = 1.0;
  bool ground = false, ortho = false, black_background = false;
  double fov = 32.0;
  std::vector<std::string> lights;  ///< "dx,dy,dz[,irradiance]"
  int width = 512, height = 512, spp = 64;
  std::uint64_t seed = 1;
  std::string sampler = "light-and-lobe";  ///< light-and-lobe, stratified or independent
  double grazing_samples = render::RenderSettings{}.grazing_samples;
  double exposure = 0.0;
  std::string tonemap = "aces";

  /// The scene description (lights parsed; throws matlas::Error on malformed values).
  render::SceneDescription scene_description() const;
  /// `others` and the files these options read (--scene, --env; names of installed assets are
  /// not files and never match): what an output must not be (core/file_io.h).
  std::vector<std::filesystem::path> input_files(std::vector<std::filesystem::path> others) const;
  render::RenderSettings settings() const;
  ToneMap tone() const;
};

/// Adds the options to a command; `image` adds --size/--spp/--seed/--sampler/--grazing-samples/
/// --exposure/--tonemap too.
void add_render_options(CLI::App& cmd, RenderOptions& o, bool image = true);

/// The options of the previews' scene that a GI scene (floor, box, a .json file: it says its own
/// lights, camera and environment) or a basis does not use.
inline constexpr const char* kPreviewSceneOptions[] = {"--env",   "--env-rotation",     "--env-intensity", "--ground",
                                                      "--light", "--ortho",            "--fov",           "--black-background",
                                                      "--sampler", "--grazing-samples"};

/// The path tracer's options: a built-in GI scene's measured object, the object's sampling
/// density and the path length.
struct PathOptions {
  std::string object = "sphere";
  std::string density = "fitted";
  std::optional<int> max_depth;
  /// The trace settings of these options and `image` (size, samples, seed); the density fitted
  /// to `model`'s database (none: the fixed lobes).
  pathtrace::TraceSettings settings(const RenderOptions& image, const Model* model) const;
};
void add_path_options(CLI::App& cmd, PathOptions& o);

/// The long names ("--env") of the options given on a command's line.
std::set<std::string> given_options(const CLI::App& cmd);
/// matlas::Error naming the first of `options` given, which does not apply to `what`.
void refuse_options(const std::set<std::string>& given, std::span<const char* const> options, const std::string& what);

}  // namespace matlas::cli
