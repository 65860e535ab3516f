#include "core/check.h"

#include <cstring>

namespace matlas {

void check_failed(const char* file, int line, const char* condition, const std::string& detail) {
  // The path from src/ on: the build's absolute prefix says nothing to a reader.
  const char* src = std::strstr(file, "src/");
  std::string message = std::string("internal check failed at ") + (src ? src + 4 : file) + ":" +
                        std::to_string(line) + ": " + condition;
  if (!detail.empty()) message += " " + detail;
  throw InternalError(message);
}

}  // namespace matlas
