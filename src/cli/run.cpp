#include "cli/run.h"

#include <atomic>
#include <exception>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/mapping_watch.h"

namespace matlas::cli {

namespace {

// Whether the running command's outputs are refused once a memory-mapped input (a model, a
// basis) read vanished pages: every command's, until it hands its inputs to a server.
std::atomic<bool> g_watch_inputs{false};

}  // namespace

void leave_mapped_inputs_to_the_server() { g_watch_inputs.store(false); }

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const Io io{out, err};
  CLI::App app{"matlas: a material atlas built from measured BRDFs (Soler et al. 2018)", "matlas"};
  app.set_version_flag("--version", std::string("matlas ") + MATLAS_VERSION);
  app.require_subcommand(1);
  app.fallthrough(false);

  for (const auto& command : registered_commands()) command.add(app, io);

  // A model truncated while a command reads it reads as zeros where its pages vanished
  // (formats/safetensors.h): the answer is wrong. No output file is committed then (the check runs
  // before each AtomicFile's rename), and the command fails after printing.
  const MappingFaultWatch inputs;
  g_watch_inputs.store(true);
  const CommitCheck inputs_intact([&inputs] {
    if (g_watch_inputs.load()) inputs.check();
  });
  try {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
    app.parse(reversed);
    if (g_watch_inputs.load()) inputs.check();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    app.exit(e, out, err);
    return 2;
  } catch (const matlas::Error& e) {
    print(err, "matlas: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    print(err, "matlas: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace matlas::cli
