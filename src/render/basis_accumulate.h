#pragma once
// The inner loop of composing an image basis: acc[0, len) += sum_i w[i] * row_i[begin, begin + len)
// over n rows of float32 or float16 values `stride` apart, with AVX2 kernels where the processor
// has them (core/cpu_features.h) and portable loops elsewhere.
#include <cstddef>
#include <cstdint>

namespace matlas::render {

/// The float value of every float16 bit pattern (65536 entries).
const float* half_table();

void accumulate_f32(const float* values, std::size_t stride, std::size_t begin, std::size_t len, const float* w,
                    int n, float* acc);
void accumulate_f16(const std::uint16_t* values, std::size_t stride, std::size_t begin, std::size_t len,
                    const float* w, int n, float* acc);

}  // namespace matlas::render
