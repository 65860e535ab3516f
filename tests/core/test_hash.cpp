// core/hash.h: xxh3-64 as libxxhash computes it, whole or in pieces, and its hex form.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "core/cpu_features.h"
#include "core/hash.h"

namespace matlas {
namespace {

TEST(Hash, EmptyInputHasXxh3sPublishedValue) {
  // XXH3_64bits of zero bytes with seed 0 (xxHash's reference test vector).
  EXPECT_EQ(xxh3_64(std::string_view{}), 0x2D06800538D394C2ull);
}

TEST(Hash, StreamingEqualsOneShotAndDependsOnEveryByte) {
  std::string text(1000, '\0');
  for (std::size_t i = 0; i < text.size(); ++i) text[i] = static_cast<char>(i * 7 + 3);
  Xxh3Hasher h;
  h.update(std::string_view(text).substr(0, 10));
  h.update(std::string_view(text).substr(10, 500));
  h.update(text.data() + 510, text.size() - 510);
  EXPECT_EQ(h.digest(), xxh3_64(text));
  std::string changed = text;
  changed[999] ^= 1;
  EXPECT_NE(xxh3_64(changed), xxh3_64(text));
}

TEST(Hash, HexIsSixteenLowerCaseDigits) {
  EXPECT_EQ(hex64(0), "0000000000000000");
  EXPECT_EQ(hex64(0xABCDEF0123456789ull), "abcdef0123456789");
}

TEST(CpuFeatures, F16cImpliesAvx2Fma) {
  if (cpu_has_avx2_fma_f16c()) {
    EXPECT_TRUE(cpu_has_avx2_fma());
  }
#if defined(__x86_64__)
  __builtin_cpu_init();
  EXPECT_EQ(cpu_has_avx2_fma(), __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"));
#endif
}

}  // namespace
}  // namespace matlas
