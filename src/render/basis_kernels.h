#pragma once
// The inner loops of ImageBasis composition (image_basis.h): acc[0, len) += sum_r w[r] *
// row_{rows[r]}[begin, begin + len) over n of the rows (`stride` values apart) named by `rows`,
// in float32 or float16 storage. Only the named rows are read: a composition of convex weights
// names its few non-zero ones.
// AVX2, FMA and F16C when the CPU has them (one row per pass), chosen at run time; portable
// otherwise.
#include <cstddef>
#include <cstdint>

namespace matlas::render::detail {

void accumulate_f32(const float* values, std::size_t stride, std::size_t begin, std::size_t len, const int* rows,
                    const float* w, int n, float* acc);
void accumulate_f16(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                    const int* rows, const float* w, int n, float* acc);

/// float16 bits -> float, all 65536 values.
const float* half_table();

}  // namespace matlas::render::detail
