// Fuzz target: RGL .bsdf files. The tensor file reader from a file (header first, then each
// field's data) and from memory must agree; an accepted file goes through the measured model
// (evaluation, and resampling onto a small MERL grid when isotropic).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <span>

#include "core/error.h"
#include "formats/rgl_bsdf.h"
#include "formats/tensor_file.h"
#include "memfile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const matlas::fuzz::MemFile file(data, size);
  std::optional<matlas::TensorFile> parsed, read;
  try {
    parsed = matlas::TensorFile::parse(std::as_bytes(std::span(data, size)), "fuzz.bsdf");
  } catch (const matlas::Error&) {
  }
  try {
    read = matlas::TensorFile::read(file.path());
  } catch (const matlas::Error&) {
  }
  if (parsed.has_value() != read.has_value()) std::abort();  // the two readers disagree
  if (!parsed) return 0;
  for (std::size_t f = 0; f < parsed->fields().size(); ++f)
    if (parsed->fields()[f].data != read->fields()[f].data) std::abort();
  try {
    const matlas::RglBsdf bsdf(std::move(*read));
    (void)bsdf.summary();
    for (double z : {0.05, 0.5, 0.99}) {
      const matlas::Vec3 wi(std::sqrt(1 - z * z), 0, z), wo(-0.3, 0.4, std::sqrt(0.75));
      (void)bsdf.eval(wi, wo);
      (void)bsdf.eval_reciprocal(wo, wi);
    }
    if (bsdf.isotropic()) (void)matlas::resample_to_merl(bsdf, nullptr, matlas::MerlDims{4, 3, 6});
  } catch (const matlas::Error&) {
  }
  return 0;
}
