// matlas: the command-line entry point, a thin wrapper over cli::run (cli/run.h). Exit codes:
// 0 success, 1 bad input or failed operation, 2 usage error.
#include <iostream>
#include <string>
#include <vector>

#include "cli/run.h"
#include "core/atomic_file.h"

int main(int argc, char** argv) {
  // An interrupted command (Ctrl-C, kill) leaves no TARGET.tmp-PID files behind.
  matlas::remove_temporaries_on_signals();
  const std::vector<std::string> args(argv + 1, argv + argc);
  return matlas::cli::run(args, std::cout, std::cerr);
}
