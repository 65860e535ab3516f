// matlas import FILE.bsdf... -o DIR: RGL measured materials resampled onto the MERL grid.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "brdf/albedo.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "core/error.h"
#include "core/file_io.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"

namespace matlas::cli {

namespace {

namespace fs = std::filesystem;

struct ImportArgs {
  std::vector<std::string> inputs;
  std::string output;
  bool check = true;
};

void run_import(const ImportArgs& a, const Io& io) {
  // Read and validate everything before writing anything.
  std::vector<RglBsdf> sources;
  std::set<std::string> names;
  for (const auto& input : a.inputs) {
    const fs::path path(input);
    if (!is_rgl_path(path))
      throw file_error(path, "not an RGL .bsdf file (import reads .bsdf files; MERL .binary files need no import)");
    RglBsdf b = RglBsdf::read(path);
    if (!b.isotropic())
      throw file_error(path, "anisotropic material (" + std::to_string(b.phi_i_count()) +
                                 " incident azimuths), not supported yet: the MERL grid holds isotropic BRDFs only");
    if (!names.insert(path.stem().string()).second)
      throw file_error(path, "two inputs would both be written as " + path.stem().string() + ".binary");
    sources.push_back(std::move(b));
  }
  const fs::path dir(a.output);
  // An output that is one of the inputs (through a link): refused before anything is written.
  const std::vector<fs::path> input_paths(a.inputs.begin(), a.inputs.end());
  for (const RglBsdf& b : sources) refuse_output_among_inputs(dir / (b.path().stem().string() + ".binary"), input_paths);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir)) throw file_error(dir, "cannot create the output folder");

  for (const RglBsdf& b : sources) {
    RglResampling r;
    const BrdfTable table = resample_to_merl(b, &r);
    const fs::path out = dir / (b.path().stem().string() + ".binary");
    write_merl(out, table);
    print(io.out, "%s -> %s\n", b.path().string().c_str(), out.string().c_str());
    if (!b.description().empty()) print(io.out, "  material        %s\n", b.description().c_str());
    print(io.out, "  source          %s\n", b.summary().c_str());
    print(io.out, "  resampled       at the centres of the %s MERL bins, RGB%s; %zu bins with a direction below the "
                "horizon stored as missing (-1)\n",
                table.dims().to_string().c_str(), b.spectral() ? " (from the spectra)" : "", r.missing_bins);
    print(io.out, "  reciprocity     the measurement and its reverse differ by %.1f %% (cosine-weighted); the table "
                "holds their least-squares reciprocal combination\n",
                100 * r.reciprocity_error);
    if (b.negative_samples())
      print(io.out, "  negative        %zu of the file's %zu reflectance samples (out-of-gamut colour or noise); "
                  "evaluation clips them at 0, as RGL's loader and Mitsuba do\n",
                  b.negative_samples(), b.reflectance_samples());
    if (r.clamped_values)
      print(io.out, "  clamped         %zu negative values stored as 0\n", r.clamped_values);
    print(io.out, "  largest value   %.4g %.4g %.4g (1/sr)\n", r.max_value[0], r.max_value[1], r.max_value[2]);
    if (a.check) {
      for (double deg : {5.0, 30.0, 60.0}) {
        const Vec3 wo = direction_at_theta(deg * kPi / 180);
        const Rgb t = half_vector_albedo([&](const Vec3& wi, const Vec3& v) { return table.lookup(wi, v); }, wo);
        const Rgb m = half_vector_albedo(
            [&](const Vec3& wi, const Vec3& v) -> Rgb { return b.eval_reciprocal(wi, v).max(0.0); }, wo);
        const double rel = ((t - m).abs() / m.max(0.01)).maxCoeff();
        // What a renderer shows from the file itself: one order (the view first), not reciprocal.
        const Rgb g = half_vector_albedo([&](const Vec3& w, const Vec3& v) { return b.eval(v, w); }, wo);
        const Rgb gap = (t - g) / g.max(0.01);
        const int worst = static_cast<int>(std::distance(gap.data(), std::max_element(gap.data(), gap.data() + 3, [](double x, double y) {
          return std::fabs(x) < std::fabs(y);
        })));
        print(io.out, "  albedo %2.0f deg   %.4f %.4f %.4f (table), %.2f %% from the model integrated directly; %+.1f %% "
                    "from the measurement as renderers evaluate it (%.4f %.4f %.4f)\n",
                    deg, t[0], t[1], t[2], 100 * rel, 100 * gap[worst], g[0], g[1], g[2]);
      }
    }
  }
}

void add_import_command(CLI::App& app, const Io& io) {
  auto args = std::make_shared<ImportArgs>();
  auto* cmd = app.add_subcommand("import", "Resample RGL .bsdf measured materials onto the MERL grid (.binary files)");
  cmd->add_option("inputs", args->inputs, "RGL .bsdf files (isotropic)")->required();
  cmd->add_option("-o,--output", args->output, "Output folder (created if needed); NAME.bsdf becomes NAME.binary")
      ->required();
  cmd->add_flag("!--no-check", args->check, "Skip the albedo check against the model (faster)");
  cmd->callback([io, args] { run_import(*args, io); });
}

}  // namespace

MATLAS_COMMAND(25, add_import_command);

}  // namespace matlas::cli
