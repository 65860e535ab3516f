#pragma once
// Where a command writes: its standard output and error streams, given by the caller (std::cout and
// std::cerr in the `matlas` executable, string streams in the tests), and printf-style
// formatting into them.
#include <ostream>

namespace matlas::cli {

struct Io {
  std::ostream& out;
  std::ostream& err;
};

/// Formats as std::printf does and writes the text to `os`.
[[gnu::format(printf, 2, 3)]] void print(std::ostream& os, const char* format, ...);

}  // namespace matlas::cli
