// matlas info FILE...: header, missing fraction, per-channel statistics and normal-incidence albedo.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "brdf/albedo.h"
#include "cli/commands.h"
#include "cli/print.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf.h"

namespace matlas::cli {

namespace {

void print_info(const std::string& path, const Io& io) {
  const BrdfTable table = read_brdf(path);  // .bsdf: resampled onto the MERL grid
  const std::size_t bins = table.bins();
  print(io.out, "%s\n", path.c_str());
  print(io.out, "  dims            %d x %d x %d (theta_h x theta_d x phi_d)%s\n", table.dims().theta_h,
              table.dims().theta_d, table.dims().phi_d,
              table.dims().is_standard() ? "" : "  [non-standard]");
  print(io.out, "  missing         %.4f%% of values\n",
              100.0 * static_cast<double>(table.missing_count()) / static_cast<double>(table.size()));
  static const char* names[] = {"red", "green", "blue"};
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v;
    v.reserve(bins);
    for (std::size_t b = 0; b < bins; ++b)
      if (table.measured(c, b)) v.push_back(table.value(c, b));
    if (v.empty()) {
      print(io.out, "  %-5s           no measured values\n", names[c]);
      continue;
    }
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    print(io.out, "  %-5s           min %.6g  median %.6g  max %.6g\n", names[c], *lo, *mid, *hi);
  }
  const Rgb albedo = normal_albedo(table);
  print(io.out, "  albedo (normal) %.4f %.4f %.4f (views within 2 deg of the normal)\n", albedo[0], albedo[1], albedo[2]);
}

}  // namespace

namespace {
void add_info_command(CLI::App& app, const Io& io) {
  auto* cmd = app.add_subcommand("info", "Describe MERL .binary BRDF files (RGL .bsdf files as resampled onto the MERL grid)");
  auto files = std::make_shared<std::vector<std::string>>();
  cmd->add_option("files", *files, "MERL .binary files")->required();
  cmd->callback([io, files] {
    for (const auto& f : *files) print_info(f, io);
  });
}
}  // namespace

MATLAS_COMMAND(20, add_info_command);

}  // namespace matlas::cli
