#pragma once
// Each subcommand lives in its own cmd_NAME.cpp and registers itself on the root app here.
// A command's callback throws matlas::Error for bad input (exit 1); CLI11 reports usage errors
// (exit 2).
#include <CLI/CLI.hpp>

namespace matlas::cli {

void add_info_command(CLI::App& app);

}  // namespace matlas::cli
