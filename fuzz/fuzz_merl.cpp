// Fuzz target: the MERL .binary reader (header, size checks, value checks, streaming reads).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/error.h"
#include "formats/merl_file.h"
#include "memfile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  matlas::fuzz::MemFile file(data, size);
  try {
    const matlas::MerlFile merl(file.path());
    if (merl.value_count() > (1u << 22)) return 0;  // valid but large: the reads below are the same
    std::vector<double> values(merl.value_count());
    merl.read_values(0, values.size(), values.data());
    merl.visit_values(values.size() / 3, values.size() - values.size() / 3,
                      [](const double*, std::size_t, std::size_t) {});
  } catch (const matlas::Error&) {
  }
  return 0;
}
