#pragma once
// A BrdfTable as the bytes of a MERL `.binary` file, in memory (for downloads): the same layout
// write_merl() writes (int32 dims, then 3 * bins float64 in stored units, little-endian).
#include <string>

#include "brdf/brdf_table.h"

namespace matlas::server {

std::string merl_bytes(const BrdfTable& table);

}  // namespace matlas::server
