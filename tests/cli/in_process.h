#pragma once
// Test helper: runs `matlas ARGS...` in this process through cli::run, capturing both streams.
#include <sstream>
#include <string>
#include <vector>

#include "cli/run.h"

namespace matlas::test {

struct CliOutput {
  int code = -1;
  std::string out, err;
};

inline CliOutput call_matlas(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  CliOutput r;
  r.code = cli::run(args, out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

}  // namespace matlas::test
