#pragma once
// Each subcommand lives in its own cmd_NAME.cpp and registers itself with MATLAS_COMMAND, so
// adding a command touches no other file. Registration order (`order`) is the order of --help.
// A command's callback throws matlas::Error for bad input (exit 1); CLI11 reports usage errors
// (exit 2). Commands write only to the streams of the Io they are given (cli/print.h).
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/print.h"

namespace matlas::cli {

/// Adds a command to `app`; its callback writes to `io`, which outlives the parse.
using CommandFactory = void (*)(CLI::App& app, const Io& io);

struct RegisteredCommand {
  int order;
  CommandFactory add;
};

/// Called at static-initialisation time by MATLAS_COMMAND.
bool register_command(int order, CommandFactory add);
/// Every registered command, sorted by order.
std::vector<RegisteredCommand> registered_commands();

/// cli::run refuses a command's outputs (files before they are committed, and the exit status
/// after) once a memory-mapped input read vanished pages (formats/mapping_watch.h). A command that
/// serves calls this first: the server checks its model itself (503, then a reload) and keeps
/// writing its caches.
void leave_mapped_inputs_to_the_server();

}  // namespace matlas::cli

// The variable is named after the factory so that several commands may share a translation unit
// (unity builds).
#define MATLAS_COMMAND(order, factory) \
  [[maybe_unused]] static const bool matlas_registered_##factory = \
      ::matlas::cli::register_command(order, factory)
