// Fuzz target: the MERL .binary reader (header, size checks, value checks, streaming reads) and
// the in-memory decoder (decode_merl), which must accept exactly the same bytes.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "formats/merl_file.h"
#include "memfile.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  matlas::fuzz::MemFile file(data, size);
  bool decoded = false, read = false;
  try {
    matlas::decode_merl(std::string_view(reinterpret_cast<const char*>(data), size), "bytes");
    decoded = true;
  } catch (const matlas::Error&) {
  }
  try {
    const matlas::MerlFile merl(file.path());
    if (merl.value_count() > (1u << 22)) return 0;  // valid but large: the reads below are the same
    std::vector<double> values(merl.value_count());
    merl.read_values(0, values.size(), values.data());
    merl.visit_values(values.size() / 3, values.size() - values.size() / 3,
                      [](const std::byte*, std::size_t, std::size_t) {});
    read = true;
  } catch (const matlas::Error&) {
    read = false;
  }
  if (decoded != read) std::abort();  // the two readers disagree
  return 0;
}
