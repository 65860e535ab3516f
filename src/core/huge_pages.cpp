#include "core/huge_pages.h"

#include <algorithm>
#include <cstdint>
#include <new>
#include <sys/mman.h>

namespace matlas {

void advise_huge_pages(void* data, std::size_t bytes) {
  if (data == nullptr) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  const std::uintptr_t last = (begin + bytes) / kHugePageBytes * kHugePageBytes;
  if (last > first) ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // a hint
}

void* allocate_huge_pages(std::size_t bytes, std::size_t alignment) {
  const bool huge = bytes >= kHugePageBytes;
  const std::size_t align = huge ? std::max(kHugePageBytes, alignment) : std::max<std::size_t>(64, alignment);
  const std::size_t rounded = (std::max<std::size_t>(bytes, 1) + align - 1) / align * align;
  void* p = std::aligned_alloc(align, rounded);
  if (p == nullptr) throw std::bad_alloc();
  if (huge) advise_huge_pages(p, rounded);
  return p;
}

}  // namespace matlas
