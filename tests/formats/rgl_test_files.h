#pragma once
// Where the real RGL files of ../shared are (synthetic ones: support/synthetic_rgl.h).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "support/synthetic_rgl.h"

namespace matlas::test {

/// ../shared/data/rgl beside the source tree (or $MATLAS_SHARED_DIR/data/rgl); empty if absent.
inline std::filesystem::path shared_rgl_dir() {
  std::filesystem::path shared = std::getenv("MATLAS_SHARED_DIR") ? std::getenv("MATLAS_SHARED_DIR")
                                                                   : std::filesystem::path(MATLAS_SOURCE_DIR) / ".." / "shared";
  const auto dir = shared / "data" / "rgl";
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) ? dir : std::filesystem::path();
}

/// The six isotropic RGL materials of ../shared/data/rgl.
inline const std::vector<std::string>& shared_rgl_names() {
  static const std::vector<std::string> names{"aurora_white_rgb", "chm_mint_rgb",  "cm_military_green_rgb",
                                              "ilm_solo_m_68_rgb", "paper_white_rgb", "vch_golden_yellow_rgb"};
  return names;
}

}  // namespace matlas::test
