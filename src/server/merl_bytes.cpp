#include "server/merl_bytes.h"

#include <bit>
#include <cstdint>
#include <cstring>

namespace matlas::server {

static_assert(std::endian::native == std::endian::little, "MERL files are little-endian");

std::string merl_bytes(const BrdfTable& table) {
  const std::int32_t dims[3] = {table.dims().theta_h, table.dims().theta_d, table.dims().phi_d};
  const auto values = table.stored();
  std::string bytes(sizeof dims + values.size() * sizeof(double), '\0');
  std::memcpy(bytes.data(), dims, sizeof dims);
  std::memcpy(bytes.data() + sizeof dims, values.data(), values.size() * sizeof(double));
  return bytes;
}

}  // namespace matlas::server
