// advise_huge_pages: the whole 2 MiB pages inside a buffer get the hint, the buffer's contents and
// its neighbours are untouched, and buffers without a whole huge page are left alone;
// allocate_huge_pages and HugePageVector: buffers of a huge page or more come 2 MiB-aligned and
// advised, smaller ones with the alignment asked for.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include <sys/mman.h>

#include "core/huge_pages.h"

namespace matlas {
namespace huge_pages_test {

/// The "hg" (huge page advised) flag of the mapping that holds `address`, from /proc/self/smaps.
bool advised(const void* address) {
  std::ifstream smaps("/proc/self/smaps");
  const auto at = reinterpret_cast<std::uintptr_t>(address);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find(':') != std::string::npos &&
        line.find('-') < line.find(' ')) {
      inside = at >= lo && at < hi;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line.find(" hg") != std::string::npos;
    }
  }
  return false;
}

/// A fresh anonymous mapping of its own (not from the allocator, which sanitizers replace).
struct Mapping {
  explicit Mapping(std::size_t size) : bytes(size) {
    data = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  }
  ~Mapping() {
    if (data != MAP_FAILED) ::munmap(data, bytes);
  }
  std::size_t bytes;
  void* data;
};

TEST(HugePages, TheWholeHugePagesInsideABufferAreAdvisedAndItsValuesKept) {
  if (!std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) GTEST_SKIP() << "no transparent huge pages";
  const std::size_t bytes = 5 * kHugePageBytes + 12345;
  Mapping m(bytes);
  ASSERT_NE(m.data, MAP_FAILED);
  auto* buffer = static_cast<unsigned char*>(m.data);
  std::memset(buffer, 7, bytes);
  advise_huge_pages(buffer, bytes);
  for (std::size_t i = 0; i < bytes; i += 4099) ASSERT_EQ(buffer[i], 7) << i;
  const auto begin = reinterpret_cast<std::uintptr_t>(buffer);
  const std::uintptr_t first = (begin + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
  EXPECT_TRUE(advised(reinterpret_cast<const void*>(first)));
  EXPECT_TRUE(advised(reinterpret_cast<const void*>(first + 3 * kHugePageBytes)));
  if (first > begin) {
    EXPECT_FALSE(advised(buffer));  // the part before the first whole huge page
  }
}

TEST(HugePages, ABufferWithoutAWholeHugePageAndANullOneAreLeftAlone) {
  Mapping m(kHugePageBytes + 4096);
  ASSERT_NE(m.data, MAP_FAILED);
  std::memset(m.data, 1, m.bytes);
  // Less than a huge page: whatever its alignment, no whole huge page inside.
  advise_huge_pages(static_cast<char*>(m.data) + 4096, kHugePageBytes - 1);
  EXPECT_FALSE(advised(static_cast<char*>(m.data) + 8192));
  advise_huge_pages(nullptr, 10 * kHugePageBytes);  // nothing to do
}

TEST(HugePages, LargeAllocationsAreWholeAdvisedHugePagesAndSmallOnesKeepTheirAlignment) {
  const bool thp = static_cast<bool>(std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled"));
  const std::size_t bytes = 3 * kHugePageBytes + 100;
  void* large = allocate_huge_pages(bytes, 4096);
  ASSERT_NE(large, nullptr);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(large) % kHugePageBytes, 0u);
  std::memset(large, 3, bytes);  // all of it writable
  if (thp) {
    EXPECT_TRUE(advised(large));
    EXPECT_TRUE(advised(static_cast<char*>(large) + 3 * kHugePageBytes));  // rounded up to whole huge pages
  }
  std::free(large);

  for (const std::size_t alignment : {std::size_t{8}, std::size_t{64}, std::size_t{4096}}) {
    void* small = allocate_huge_pages(kHugePageBytes - 1, alignment);
    ASSERT_NE(small, nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small) % std::max<std::size_t>(alignment, 64), 0u) << alignment;
    std::memset(small, 1, kHugePageBytes - 1);
    std::free(small);
  }
  void* empty = allocate_huge_pages(0);  // a valid pointer, as malloc(0) may give
  std::free(empty);
}

TEST(HugePages, AHugePageVectorHoldsItsValuesInAdvisedHugePages) {
  HugePageVector<float> v(kHugePageBytes / sizeof(float) + 1);  // value-initialised: all zero
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data()) % kHugePageBytes, 0u);
  for (std::size_t i = 0; i < v.size(); i += 1021) ASSERT_EQ(v[i], 0.0f) << i;
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>(i % 977);
  HugePageVector<float> copy = v;
  EXPECT_EQ(copy, v);
  if (std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled")) {
    EXPECT_TRUE(advised(copy.data()));
  }
  HugePageVector<int> small(10, 7);  // under a huge page: an ordinary aligned block
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.data()) % alignof(int), 0u);
  EXPECT_EQ(small[9], 7);
}

}  // namespace huge_pages_test
}  // namespace matlas
