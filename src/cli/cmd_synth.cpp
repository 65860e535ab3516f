// matlas synth -o DIR [--preset demo | --count N --seed S]: writes a synthetic MERL database of
// analytic BRDFs (conductors, plastics, matte paints, Blinn-Phong), one NAME.binary per material.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "brdf/catalog.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "core/error.h"
#include "formats/synth_database.h"

namespace matlas::cli {

namespace {

struct SynthOptions {
  std::string out;
  std::string preset;
  int count = 0;
  std::uint64_t seed = 1;
};

void run_synth(const SynthOptions& o, const Io& io) {
  if (!o.preset.empty() && o.count > 0)
    throw Error("synth: give either --preset or --count, not both");
  if (!o.preset.empty() && o.preset != "demo")
    throw Error("synth: unknown preset '" + o.preset + "' (known: demo)");
  const std::vector<SynthMaterial> catalog =
      o.count > 0 ? random_catalog(o.count, o.seed) : demo_catalog();
  TerminalProgress progress;
  const auto written = write_database(o.out, catalog, progress);
  for (std::size_t i = 0; i < written.size(); ++i)
    print(io.out, "%s\t%s\n", written[i].string().c_str(), describe(catalog[i].brdf).c_str());
  print(io.err, "wrote %zu MERL files to %s\n", written.size(), o.out.c_str());
}

void add_synth_command(CLI::App& app, const Io& io) {
  auto opts = std::make_shared<SynthOptions>();
  auto* cmd = app.add_subcommand(
      "synth", "Write a synthetic MERL database of analytic BRDFs (about 35 MB per material)");
  cmd->add_option("-o,--output", opts->out, "Output folder (created if needed)")->required();
  cmd->add_option("--preset", opts->preset,
                  "Fixed set of materials: 'demo' (about 30 metals, plastics, paints; the default)");
  auto* count = cmd->add_option("--count", opts->count, "Draw N random materials instead of a preset")
                    ->check(CLI::Range(1, 100000));
  cmd->add_option("--seed", opts->seed, "Seed of the random draw (same seed, same files; default 1)")
      ->needs(count);
  cmd->callback([io, opts] { run_synth(*opts, io); });
}

}  // namespace

MATLAS_COMMAND(80, add_synth_command);

}  // namespace matlas::cli
