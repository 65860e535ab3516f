#pragma once
// Finding the installed rendering assets (scripts/install-assets.sh): environment maps in
// ASSETS/hdri/NAME.exr and meshes in ASSETS/models/NAME.glb.
//
// The assets folder is, in order: $MATLAS_ASSETS; <exe dir>/../assets; <exe dir>/assets;
// ./assets. Names may always be replaced by file paths.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace matlas {

/// The first existing assets folder of the search order above, or nullopt.
std::optional<std::filesystem::path> assets_dir();

/// An environment map: an existing file path is returned as is; otherwise NAME is looked up as
/// ASSETS/hdri/NAME.exr. Throws matlas::Error listing the installed maps when not found.
std::filesystem::path resolve_environment(const std::string& name_or_path);

/// A mesh: an existing file path is returned as is; "bunny", "suzi"/"suzanne" (and any other
/// NAME) are looked up as ASSETS/models/NAME.glb. Throws matlas::Error when not found.
std::filesystem::path resolve_mesh(const std::string& name_or_path);

/// Names of the installed environment maps (sorted), empty without assets.
std::vector<std::string> installed_environments();

}  // namespace matlas
