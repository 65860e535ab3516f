#include "cli/print.h"

#include <cstdarg>
#include <cstdio>
#include <string>

namespace matlas::cli {

void print(std::ostream& os, const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int length = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  if (length > 0) {
    std::string text(static_cast<std::size_t>(length) + 1, '\0');
    std::vsnprintf(text.data(), text.size(), format, again);
    os.write(text.data(), length);
  }
  va_end(again);
}

}  // namespace matlas::cli
