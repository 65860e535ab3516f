#pragma once
// IEEE 754 binary16 storage of float values (bases, coefficient files, f16 models): the portable
// scalar conversions; hot loops use the processor's F16C instructions where they have them
// (render/basis_kernels.cpp).
#include <cstdint>

namespace matlas {

/// IEEE half <-> float conversions (round to nearest even), portable.
std::uint16_t float_to_half(float f);
float half_to_float(std::uint16_t h);

}  // namespace matlas
