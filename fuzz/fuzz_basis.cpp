// Fuzz target: the two image-basis files (safetensors): the preview image basis
// (render/image_basis.h; then composed, directly and through its low-rank form) and the GI basis
// (atlas/gi_basis.h; then composed).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "atlas/gi_basis.h"
#include "core/error.h"
#include "memfile.h"
#include "render/image_basis.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const matlas::fuzz::MemFile file(data, size);
  try {
    const matlas::render::ImageBasis basis = matlas::render::ImageBasis::open(file.path());
    const Eigen::VectorXd w = Eigen::VectorXd::Constant(basis.count(), 1.0 / basis.count());
    std::vector<float> rgb(static_cast<std::size_t>(basis.width()) * static_cast<std::size_t>(basis.height()) * 3);
    basis.compose(w, rgb.data());
    basis.compose_low_rank(w, rgb.data());
  } catch (const matlas::Error&) {
  }
  try {
    const matlas::atlas::GiBasis gi = matlas::atlas::GiBasis::load(file.path());
    (void)gi.compose(Eigen::VectorXd::Constant(gi.count(), 0.5));
  } catch (const matlas::Error&) {
  }
  return 0;
}
