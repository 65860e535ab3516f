#pragma once
// The `matlas` command as a function: what main() does, callable in-process (the tests call it).
#include <ostream>
#include <string>
#include <vector>

namespace matlas::cli {

/// Runs `matlas ARGS...` (args without the program name, e.g. {"latent", "m.matlas"}) writing to
/// `out` and `err`, and returns the exit code: 0 success, 1 bad input or failed operation
/// (the message on `err`), 2 usage error. --help and --version print to `out` and return 0.
/// Installs no signal handlers (main() does); `serve` and `demo` serve until SIGINT/SIGTERM.
int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace matlas::cli
