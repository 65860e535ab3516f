#pragma once
// A small model for the acquisition tests (12 smooth synthetic materials on the small grid,
// q = 2), built once per test program, and samples of any table at random directions.
#include <memory>
#include <random>
#include <vector>

#include "formats/sample_file.h"
#include "manifold/build.h"
#include "manifold/model.h"
#include "manifold/synthetic_database.h"
#include "support/temp_dir.h"

namespace matlas::test {

struct AcquisitionModel {
  TempDir dir{"matlas-acquisition"};
  std::vector<std::filesystem::path> paths;
  std::unique_ptr<Model> model;
  AcquisitionModel() {
    paths = write_database(dir / "db", 12, 5);
    BuildOptions o;
    o.dim = 2;
    build_model(MaterialSet::open({dir / "db"}), o, dir / "m.matlas");
    model = std::make_unique<Model>(Model::open(dir / "m.matlas"));
  }
  static const AcquisitionModel& get() {
    static const AcquisitionModel shared;
    return shared;
  }
};

/// A uniformly random direction of the upper hemisphere below 80 degrees.
inline Vec3 acquisition_direction(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 0.18 + 0.82 * u(rng), phi = 6.283185307179586 * u(rng);
  const double s = std::sqrt(1 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

/// `count` samples of `table` (its bin values) at random direction pairs.
inline std::vector<MeasuredSample> sample_table(const BrdfTable& table, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<MeasuredSample> out;
  for (int k = 0; k < count; ++k) {
    MeasuredSample s;
    s.wi = acquisition_direction(rng);
    s.wo = acquisition_direction(rng);
    const std::size_t bin = bin_of(table.dims(), s.wi, s.wo);
    for (int c = 0; c < 3; ++c) s.value[c] = table.value(c, bin);
    s.measured = true;
    s.line = k + 2;
    out.push_back(s);
  }
  return out;
}

/// Relative L2 distance of two tables over the model's kept values.
inline double acquisition_error(const BrdfTable& a, const BrdfTable& b, const Model& m) { return relative_l2(a, b, m); }

}  // namespace matlas::test
