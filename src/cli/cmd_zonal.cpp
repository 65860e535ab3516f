// matlas zonal: rotated-ZH coefficients of every material of a database or model (issue 12),
// for real-time shading (docs/REALTIME.md).
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "atlas/model_zonal.h"
#include "cli/commands.h"
#include "cli/print.h"
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
  zonal::ProjectionSettings settings{32, 32, 128, 256};
};

bool is_model(const std::vector<std::string>& inputs) {
  return inputs.size() == 1 && std::filesystem::path(inputs[0]).extension() == ".matlas";
}

void run_zonal(const ZonalArgs& a, const Io& io) {
  const DType storage = a.storage == "f16" ? DType::F16 : DType::F32;
  const auto start = std::chrono::steady_clock::now();
  const zonal::ZonalProjector projector(a.settings);
  zonal::CoefficientSet set;
  set.settings = a.settings;
  std::vector<std::filesystem::path> paths(a.inputs.begin(), a.inputs.end());
  refuse_output_among_inputs(a.output, paths);
  if (is_model(a.inputs)) {
    set = atlas::model_coefficients(Model::open(a.inputs[0]), a.settings);
  } else {
    TerminalProgress progress;
    const MaterialSet materials = MaterialSet::open(paths, progress);
    std::vector<std::filesystem::path> files;  // the files of the folders given
    for (std::size_t i = 0; i < materials.size(); ++i) files.push_back(materials.file(i).path());
    refuse_output_among_inputs(a.output, files);
    set.names = materials.names();
    set.materials.resize(materials.size());
    for (std::size_t i = 0; i < materials.size(); ++i) {
      const MerlFile& file = materials.file(i);
      BrdfTable table(file.dims(), ValueBuffer::Uninitialized{});
      file.read_values(0, file.value_count(), table.stored().data());
      set.materials[i] = projector.project(table);
    }
  }
  const double error = zonal::write_coefficients(a.output, set, storage);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  print(io.out, "wrote %s: %zu materials, L = %d (%zu coefficients) x %d view angles, %s (storage error %.2e of the "
              "largest coefficient), %.2f s\n",
              a.output.c_str(), set.materials.size(), a.settings.bands, projector.basis().size(),
              a.settings.theta_o_count, a.storage.c_str(), error, seconds);
}

void add_zonal_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("zonal", "Rotated zonal-harmonic coefficients of a database or model (real-time shading)");
  auto a = std::make_shared<ZonalArgs>();
  cmd->add_option("inputs", a->inputs, "A .matlas model, or MERL/RGL folders and files")->required();
  cmd->add_option("-o,--output", a->output, "Output coefficient file (.safetensors)")->required();
  cmd->add_option("--bands", a->settings.bands, "Highest band L")->check(CLI::Range(0, 128))->capture_default_str();
  cmd->add_option("--theta-o", a->settings.theta_o_count, "View-angle samples")
      ->check(CLI::Range(1, 1024))->capture_default_str();
  cmd->add_option("--storage", a->storage, "f32 or f16")->check(CLI::IsMember({"f32", "f16"}))->capture_default_str();
  cmd->callback([io, a] { run_zonal(*a, io); });
}

}  // namespace

MATLAS_COMMAND(62, add_zonal_command);

}  // namespace matlas::cli
