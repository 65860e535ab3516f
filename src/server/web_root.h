#pragma once
// Where the built web UI (web/dist) is found at run time. The files are served from disk, never
// fetched from the network. Search order:
//   1. an explicit folder (`matlas serve --web-root DIR`),
//   2. the MATLAS_WEB_ROOT environment variable,
//   3. next to the executable: EXE_DIR/web/dist, EXE_DIR/../web/dist (a build folder inside the
//      repository, e.g. build/matlas), EXE_DIR/../../web/dist, EXE_DIR/../share/matlas/web.
// A folder counts only if it holds index.html.
#include <filesystem>
#include <optional>

namespace matlas::server {

/// The web root, or nullopt when none is found. An explicit folder without index.html throws
/// matlas::Error naming it.
std::optional<std::filesystem::path> find_web_root(const std::filesystem::path& explicit_dir = {});

/// The running executable's path (/proc/self/exe), empty if unknown.
std::filesystem::path executable_path();

}  // namespace matlas::server
