// Fuzz target: parsing and validation of JSON request bodies (server/request_parsing.h).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "server/http_error.h"
#include "server/request_parsing.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string body(reinterpret_cast<const char*>(data), size);
  static const matlas::server::LatentDomain domain =
      matlas::server::LatentDomain::around(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1));
  try {
    const nlohmann::json j = matlas::server::parse_json_object(body);
    try { (void)matlas::server::parse_latent(j, "x", domain); } catch (const matlas::Error&) {}
    try { (void)matlas::server::parse_int(j, "top", 0, 100, 8); } catch (const matlas::Error&) {}
    try { (void)matlas::server::parse_number(j, "phi_d", 0, 180, 90); } catch (const matlas::Error&) {}
    try { (void)matlas::server::parse_choice(j, "env", {"studio", "city"}, "studio"); } catch (const matlas::Error&) {}
  } catch (const matlas::Error&) {
  }
  try {
    (void)matlas::server::parse_int_text(body, "index", 0, 1 << 30);
  } catch (const matlas::Error&) {
  }
  return 0;
}
