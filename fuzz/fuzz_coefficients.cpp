// Fuzz target: the zonal coefficient file (safetensors: metadata, shapes, F32/F16 values).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "core/error.h"
#include "memfile.h"
#include "zonal/coefficient_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const matlas::fuzz::MemFile file(data, size);
  try {
    const matlas::zonal::CoefficientSet set = matlas::zonal::read_coefficients(file.path());
    // What the reader promises: one coefficient block per name, each of the settings' layout.
    if (set.materials.size() != set.names.size()) std::abort();
    for (const auto& m : set.materials)
      if (m.bands != set.settings.bands || m.theta_o_count != set.settings.theta_o_count) std::abort();
  } catch (const matlas::Error&) {
  }
  return 0;
}
