#pragma once
// Transparent huge pages for large buffers.
//
// A fresh allocation of hundreds of MB (the map grid's weights at n = 1000: 1000 x 16,384 doubles,
// 131 MB; a build pass's blocks and read buffers) is paged in on first touch, 4 KiB at a time,
// and then walked through 4 KiB translations: on a virtual machine each fault is costly (on the
// 2-core AMD EPYC VM the faults of the map layer's fresh matrices took about a quarter of an
// albedo layer's time, docs/BENCHMARKS.md "Huge pages for the grid's weights"), and so is
// pinning 4 KiB pages for direct reads. Where the kernel gives huge pages only on request
// (transparent_hugepage "madvise", Debian's default), asking for them on the buffer before it
// is touched makes each fault map 2 MiB.
#include <cstddef>
#include <cstdlib>
#include <vector>

namespace matlas {

/// Bytes of a huge page (x86-64: 2 MiB).
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Asks for huge pages on the whole 2 MiB-aligned pages inside [data, data + bytes) (madvise
/// MADV_HUGEPAGE): a hint; nothing happens where the buffer holds no whole huge page or where the
/// kernel refuses.
void advise_huge_pages(void* data, std::size_t bytes);

/// `bytes` of uninitialised memory aligned to `alignment` (a power of two), to be released with
/// std::free: from a huge page up, 2 MiB-aligned, rounded up to whole huge pages and advised
/// (advise_huge_pages); smaller, aligned to max(alignment, 64). Throws std::bad_alloc.
void* allocate_huge_pages(std::size_t bytes, std::size_t alignment = 64);

/// A standard allocator through allocate_huge_pages: a std::vector of it (HugePageVector) gets
/// huge pages for its storage when that is a huge page or more.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(allocate_huge_pages(n * sizeof(T), alignof(T))); }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept {
    return true;
  }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace matlas
