#pragma once
// Transparent huge pages for large buffers that are written once right after allocation.
//
// A fresh allocation of hundreds of MB (the map grid's weights at n = 1000: 1000 x 16,384 doubles,
// 131 MB) is paged in on first touch, 4 KiB at a time: on a virtual machine each fault is
// costly (on the 2-core AMD EPYC VM the faults of the map layer's fresh matrices took about a
// quarter of an albedo layer's time, docs/BENCHMARKS.md "Huge pages for the grid's weights"). Where the kernel gives
// huge pages only on request (transparent_hugepage "madvise", Debian's default), asking for them
// on the buffer before it is touched makes each fault map 2 MiB.
#include <cstddef>

namespace matlas {

/// Bytes of a huge page (x86-64: 2 MiB).
inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

/// Asks for huge pages on the whole 2 MiB-aligned pages inside [data, data + bytes) (madvise
/// MADV_HUGEPAGE): a hint; nothing happens where the buffer holds no whole huge page or where the
/// kernel refuses.
void advise_huge_pages(void* data, std::size_t bytes);

}  // namespace matlas
