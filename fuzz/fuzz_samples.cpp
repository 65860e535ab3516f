// Fuzz target: sample files (CSV and JSON measurements, formats/sample_file.h), as `matlas
// fit-samples` and the server's upload read them.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.h"
#include "formats/sample_file.h"

namespace {

/// What the reader promises of every sample it returns.
void check(const matlas::SampleFile& file) {
  for (const auto& s : file.samples) {
    if (!(std::abs(s.wi.norm() - 1) < 1e-9) || !(std::abs(s.wo.norm() - 1) < 1e-9)) std::abort();
    if (!(s.wi.z() > 0) || !(s.wo.z() > 0)) std::abort();
    if (s.measured && (!s.value.allFinite() || (s.value < 0).any() || !s.sigma.allFinite() || (s.sigma < 0).any()))
      std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (bool skip : {false, true}) {
    matlas::SampleReadOptions options;
    options.skip_invalid = skip;
    try {
      check(matlas::parse_samples(text, "fuzz", options));
    } catch (const matlas::Error&) {
    }
  }
  return 0;
}
