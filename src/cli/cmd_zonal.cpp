// matlas zonal: rotated-ZH coefficients of every material of a database or model (issue 12),
// for real-time shading (docs/REALTIME.md).
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "atlas/model_zonal.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "cli/world.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/parallel.h"
#include "manifold/material_set.h"
#include "manifold/model.h"
#include "zonal/coefficient_file.h"

namespace matlas::cli {

namespace {

struct ZonalArgs {
  std::vector<std::string> inputs;
  std::string output, storage = "f32";
  std::vector<std::string> lobes = {"none"};  ///< none, default, or sharpnesses (checked by CLI11)
  zonal::ProjectionSettings settings{32, 32, 128, 256};
};

bool is_model(const std::vector<std::string>& inputs) {
  return inputs.size() == 1 && std::filesystem::path(inputs[0]).extension() == ".matlas";
}

void run_zonal(ZonalArgs a, const Io& io) {
  if (a.lobes == std::vector<std::string>{"default"}) a.settings.lobes = zonal::kDefaultLobes;
  else if (a.lobes != std::vector<std::string>{"none"}) {
    for (const std::string& item : a.lobes) {
      if (item == "none" || item == "default") throw Error("--lobes: 'none' and 'default' stand alone, not in a list");
      a.settings.lobes.push_back(std::stod(item));  // a number: CLI::Number checked it
    }
    zonal::validate_lobes(a.settings.lobes);
  }
  // Under mpirun every rank projects its share of the tables; rank 0 gathers them and writes.
  Communicator& comm = world();
  const DType storage = a.storage == "f16" ? DType::F16 : DType::F32;
  const auto start = std::chrono::steady_clock::now();
  zonal::CoefficientSet set;
  std::vector<std::filesystem::path> paths(a.inputs.begin(), a.inputs.end());
  refuse_output_among_inputs(a.output, paths);
  TerminalProgress progress(comm.is_root());
  if (is_model(a.inputs)) {
    std::optional<Model> model;
    run_collectively(comm, [&] { model.emplace(Model::open(a.inputs[0])); });
    set = atlas::model_coefficients(*model, a.settings, comm);
  } else {
    std::optional<MaterialSet> materials;
    run_collectively(comm, [&] {
      materials.emplace(MaterialSet::open(paths, progress, 1));  // each table is projected on its own
      std::vector<std::filesystem::path> files;  // the files of the folders given
      for (std::size_t i = 0; i < materials->size(); ++i) files.push_back(materials->file(i).path());
      refuse_output_among_inputs(a.output, files);
    });
    set = atlas::database_coefficients(*materials, a.settings, comm, progress);
  }
  double error = 0;
  run_collectively(comm, [&] {
    if (comm.is_root()) error = zonal::write_coefficients(a.output, set, storage);
  });
  if (!comm.is_root()) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::size_t coefficients = static_cast<std::size_t>(a.settings.bands + 1) * static_cast<std::size_t>(a.settings.bands + 2) / 2;
  print(io.out, "wrote %s: %zu material%s, L = %d (%zu coefficients) x %d view angles, %s (storage error %.2e of the "
              "largest coefficient), %.2f s%s\n",
              a.output.c_str(), set.materials.size(), set.materials.size() == 1 ? "" : "s", a.settings.bands,
              coefficients, a.settings.theta_o_count,
              a.storage.c_str(), error, seconds,
              comm.size() > 1 ? (", " + std::to_string(comm.size()) + " MPI ranks").c_str() : "");
}

void add_zonal_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("zonal", "Rotated zonal-harmonic coefficients of a database or model (real-time shading)");
  auto a = std::make_shared<ZonalArgs>();
  cmd->add_option("inputs", a->inputs, "A .matlas model, or MERL/RGL folders and files")->required();
  cmd->add_option("-o,--output", a->output, "Output coefficient file (.safetensors)")->required();
  cmd->add_option("--bands", a->settings.bands, "Highest band L")->check(CLI::Range(0, 128))->capture_default_str();
  cmd->add_option("--theta-o", a->settings.theta_o_count, "View-angle samples")
      ->check(CLI::Range(1, 1024))->capture_default_str();
  cmd->add_option("--lobes", a->lobes,
                  "Sharp lobes fitted beside the expansion: none, default (64,256,1024,4096, as the viewer) or a "
                  "comma-separated list of sharpnesses")
      ->delimiter(',')
      ->check(CLI::IsMember({"none", "default"}) | CLI::Number)
      ->capture_default_str();
  cmd->add_option("--ring-floor", a->settings.ring_floor,
                  "Weight each view angle's bands so that the slice rings no lower than this times its median "
                  "level (docs/REALTIME.md; the viewer: 0.05); negative: the plain truncation")
      ->check(CLI::Range(-1.0, 1.0))->capture_default_str();
  cmd->add_option("--storage", a->storage, "f32 or f16")->check(CLI::IsMember({"f32", "f16"}))->capture_default_str();
  cmd->callback([io, a] { run_zonal(*a, io); });
}

}  // namespace

MATLAS_COMMAND(62, add_zonal_command);

}  // namespace matlas::cli
