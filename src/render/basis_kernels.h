#pragma once
// The inner loops of ImageBasis composition (image_basis.h): acc[0, len) += sum_i w[i] *
// row_i[begin, begin + len) over n rows `stride` values apart, in float32 or float16 storage.
// AVX2/FMA (and F16C for halves) when the CPU has them, chosen at run time; portable otherwise.
#include <cstddef>
#include <cstdint>

namespace matlas::render::detail {

void accumulate_f32(const float* values, std::size_t stride, std::size_t begin, std::size_t len, const float* w,
                    int n, float* acc);
void accumulate_f16(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                    const float* w, int n, float* acc);

/// float16 bits -> float, all 65536 values.
const float* half_table();

}  // namespace matlas::render::detail
