#include "core/huge_pages.h"

#include <cstdint>
#include <sys/mman.h>

namespace matlas {

void advise_huge_pages(void* data, std::size_t bytes) {
  if (data == nullptr) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  const std::uintptr_t last = (begin + bytes) / kHugePageBytes * kHugePageBytes;
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // a hint
}

}  // namespace matlas
