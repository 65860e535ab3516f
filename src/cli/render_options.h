#pragma once
// Command-line options shared by the rendering commands (render, basis, map, gallery): scene,
// lighting, camera, image size, samples and tone mapping.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "formats/image_io.h"
#include "render/render.h"
#include "render/scene.h"

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

}  // namespace matlas::cli
