// matlas: the command-line entry point. Exit codes: 0 success, 1 bad input or failed operation,
// 2 usage error.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/atomic_file.h"
#include "core/error.h"

int main(int argc, char** argv) {
  // An interrupted command (Ctrl-C, kill) leaves no TARGET.tmp-PID files behind.
  matlas::remove_temporaries_on_signals();
  CLI::App app{"matlas: a material atlas built from measured BRDFs (Soler et al. 2018)", "matlas"};
  app.set_version_flag("--version", std::string("matlas ") + MATLAS_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);

  for (const auto& command : matlas::cli::registered_commands()) command.add(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const matlas::Error& e) {
    std::fprintf(stderr, "matlas: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "matlas: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
