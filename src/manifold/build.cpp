#include "manifold/build.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <sstream>

#include <nlohmann/json.hpp>
#include <xxhash.h>

#include "core/error.h"
#include "formats/safetensors.h"
#include "gp/initialize.h"
#include "gp/likelihood.h"
#include "gp/posterior.h"
#include "manifold/column_blocks.h"
#include "manifold/model_format.h"

namespace matlas {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string hex(std::uint64_t h) {
  std::ostringstream s;
  s << std::hex << std::setw(16) << std::setfill('0') << h;
  return s.str();
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream s;
  s << std::put_time(&tm, "%Y-%m-%dT%H:%M:%SZ");
  return s.str();
}

void validate(const MaterialSet& set, const BuildOptions& o) {
  if (o.dim < 1 || o.dim > 10)
    throw Error("--dim must be between 1 and 10, got " + std::to_string(o.dim));
  if (!(o.nugget > 0.0) || o.nugget > 1.0)
    throw Error("--nugget must be in (0, 1], got " + std::to_string(o.nugget));
  if (static_cast<std::size_t>(o.dim) >= set.size())
    throw Error("--dim " + std::to_string(o.dim) + " needs more than " + std::to_string(o.dim) +
                " materials; the input has " + std::to_string(set.size()));
}

/// Identical (or numerically identical) materials make K singular in the limit and the layout
/// meaningless: refuse them with the names.
void reject_duplicates(const MaterialSet& set, const Eigen::MatrixXd& s) {
  const double scale = s.diagonal().mean();
  if (!(scale > 0.0)) throw Error("all input materials are identical: nothing to map");
  for (Eigen::Index i = 0; i < s.rows(); ++i)
    for (Eigen::Index j = i + 1; j < s.rows(); ++j) {
      const double d2 = s(i, i) + s(j, j) - 2.0 * s(i, j);
      if (d2 <= 1e-12 * scale)
        throw Error("materials '" + set.name(static_cast<std::size_t>(i)) + "' and '" +
                    set.name(static_cast<std::size_t>(j)) +
                    "' are identical (duplicate files?): remove one of them");
    }
}

/// The value-index -> kept-column map.
std::vector<std::int32_t> column_map(const std::vector<bool>& kept) {
  std::vector<std::int32_t> map(kept.size(), -1);
  std::int32_t next = 0;
  for (std::size_t v = 0; v < kept.size(); ++v)
    if (kept[v]) map[v] = next++;
  return map;
}

}  // namespace

BuildReport build_model(const MaterialSet& set, const BuildOptions& options, const fs::path& output,
                        ProgressSink& progress) {
  validate(set, options);
  BuildReport report;
  const auto n = static_cast<Eigen::Index>(set.size());
  const int q = options.dim;

  // Pass 1: mask, mean, Gram matrices, albedo curves, hashes.
  auto t0 = std::chrono::steady_clock::now();
  const GramResult g = accumulate_gram(set, options.layout, options.block_columns, progress);
  report.pass1_seconds = seconds_since(t0);
  report.kept_columns = g.kept_columns;
  report.dropped_columns = set.value_count() - g.kept_columns;
  reject_duplicates(set, g.gram);
  progress.message("kept " + std::to_string(g.kept_columns) + " of " +
                   std::to_string(set.value_count()) + " columns (" +
                   std::to_string(report.dropped_columns) +
                   " dropped: not measured in every material)");

  // Latent placement.
  t0 = std::chrono::steady_clock::now();
  gp::LikelihoodProblem problem;
  problem.gram = g.layout_gram;
  problem.columns = static_cast<double>(g.kept_columns);
  problem.kernel = gp::Kernel{1.0, options.nugget};
  const Eigen::MatrixXd x0 = gp::pca_initialization(problem, q);
  report.optimization = gp::optimize_latent(problem, x0, options.optimize, progress);
  report.log_likelihood = report.optimization.value;
  report.optimize_seconds = seconds_since(t0);
  const gp::GpPosterior posterior(report.optimization.latent, problem.kernel);  // checks K is PD

  // Model file: small tensors, then pass 2 streams the centred data.
  t0 = std::chrono::steady_clock::now();
  const std::vector<std::int32_t> columns = column_map(g.kept);
  const auto d = static_cast<std::int64_t>(g.kept_columns);
  const DType storage = options.storage == Storage::f16 ? DType::F16 : DType::F32;
  const Eigen::MatrixXd latent = report.optimization.latent;
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor latent_rows = latent;
  const RowMajor gram_rows = g.gram;
  const RowMajor albedo_rows = g.albedo;
  const Eigen::VectorXf mean_f = g.mean.cast<float>();

  json sources = json::array();
  for (std::size_t i = 0; i < set.size(); ++i)
    sources.push_back({{"name", set.name(i)},
                       {"file", set.file(i).path().filename().string()},
                       {"path", fs::absolute(set.file(i).path()).string()},
                       {"xxh3_64", hex(g.hashes[i])}});
  XXH3_state_t* small_hash = XXH3_createState();
  XXH3_64bits_reset(small_hash);
  for (const auto& [ptr, bytes] :
       {std::pair<const void*, std::size_t>{latent_rows.data(), latent_rows.size() * 8u},
        {gram_rows.data(), gram_rows.size() * 8u},
        {albedo_rows.data(), albedo_rows.size() * 8u},
        {mean_f.data(), mean_f.size() * 4u},
        {columns.data(), columns.size() * 4u}})
    XXH3_64bits_update(small_hash, ptr, bytes);
  const std::uint64_t small_checksum = XXH3_64bits_digest(small_hash);
  XXH3_freeState(small_hash);

  json meta = {
      {"format", model_format::kFormatName},
      {"format_version", model_format::kVersion},
      {"matlas_version", MATLAS_VERSION},
      {"created", utc_now()},
      {"names", set.names()},
      {"count", n},
      {"dim", q},
      {"grid", {set.dims().theta_h, set.dims().theta_d, set.dims().phi_d}},
      {"kernel", {{"type", "squared-exponential"}, {"lengthscale", 1.0}, {"nugget", options.nugget}}},
      {"data_layout",
       "data[c, i] = z_i[v] for the kept column c of value index v (value_column[v] = c; "
       "v = channel * bins + bin; physical units); m(x)[v] = (1 - sum w) mean[c] + sum_i w_i data[c, i]"},
      {"storage", dtype_name(storage)},
      {"layout_transform", options.layout.to_string()},
      {"log_likelihood", report.log_likelihood},
      {"optimizer",
       {{"method", gp::to_string(options.optimize.method)},
        {"iterations", report.optimization.iterations},
        {"evaluations", report.optimization.evaluations},
        {"seconds", report.optimization.seconds},
        {"stop_reason", report.optimization.stop_reason}}},
      {"kept_columns", g.kept_columns},
      {"dropped_columns", report.dropped_columns},
      {"albedo", {{"angles", 90}, {"theta_o", "bin centres of 90 uniform bins over [0, 90) degrees"},
                  {"quadrature", "cosine-weighted 64x64 midpoint rule, nearest-bin lookup"}}},
      {"sources", sources},
      {"small_tensors_xxh3_64", hex(small_checksum)},
  };

  SafetensorsWriter writer;
  writer.add_metadata(model_format::kMetadataKey, meta.dump());
  writer.declare(model_format::kLatent, DType::F64, {n, q});
  writer.declare(model_format::kGram, DType::F64, {n, n});
  writer.declare(model_format::kAlbedo, DType::F64, {n, 90, 3});
  writer.declare(model_format::kMean, DType::F32, {d});
  writer.declare(model_format::kValueColumn, DType::I32, {static_cast<std::int64_t>(columns.size())});
  writer.declare(model_format::kData, storage, {d, n});
  writer.begin(output);
  writer.write(latent_rows.data(), latent_rows.size() * 8u);
  writer.write(gram_rows.data(), gram_rows.size() * 8u);
  writer.write(albedo_rows.data(), albedo_rows.size() * 8u);
  writer.write(mean_f.data(), mean_f.size() * 4u);
  writer.write(columns.data(), columns.size() * 4u);

  double error2 = 0.0, norm2 = 0.0;
  std::vector<float> out_f32;
  std::vector<std::uint16_t> out_f16;
  std::vector<std::uint64_t> hashes;
  std::vector<Eigen::Index> tile_columns;
  BlockOptions block_options;
  block_options.block_columns = options.block_columns;
  block_options.label = "pass 2/2: data";
  block_options.hashes = &hashes;
  for_each_column_block(set, [&](const ColumnBlock& block) {
    // A tiled transpose of the kept columns into column-interleaved rows of n input values.
    std::size_t kept_here = 0;
    for (std::size_t j = 0; j < block.count; ++j) kept_here += block.kept[j];
    const std::size_t un = static_cast<std::size_t>(n);
    out_f32.resize(kept_here * un);
    constexpr std::size_t kTile = 64;
    std::size_t out_column = 0;
    for (std::size_t j0 = 0; j0 < block.count; j0 += kTile) {
      tile_columns.clear();
      for (std::size_t j = j0; j < std::min(block.count, j0 + kTile); ++j)
        if (block.kept[j]) tile_columns.push_back(static_cast<Eigen::Index>(j));
      for (Eigen::Index i = 0; i < n; ++i) {
        const double* row = block.values.row(i).data();
        float* out = out_f32.data() + out_column * un + static_cast<std::size_t>(i);
        for (std::size_t t = 0; t < tile_columns.size(); ++t) {
          const double exact = row[tile_columns[t]];
          const float rounded = static_cast<float>(exact);
          out[t * un] = rounded;
          norm2 += exact * exact;
          error2 += (rounded - exact) * (rounded - exact);
        }
      }
      out_column += tile_columns.size();
    }
    if (storage == DType::F16) {
      // Re-measure the error against half precision: the value stored is half(float(x)).
      out_f16.resize(out_f32.size());
      for (std::size_t e = 0; e < out_f32.size(); ++e) {
        out_f16[e] = float_to_half(out_f32[e]);
        const double rounding = static_cast<double>(half_to_float(out_f16[e])) - out_f32[e];
        error2 += rounding * rounding;
      }
      writer.write(out_f16.data(), out_f16.size() * 2u);
    } else {
      writer.write(out_f32.data(), out_f32.size() * 4u);
    }
  }, block_options, progress);
  for (std::size_t i = 0; i < set.size(); ++i)
    if (hashes[i] != g.hashes[i])
      throw file_error(set.file(i).path(), "changed while the model was being built; run again");
  writer.commit();
  report.pass2_seconds = seconds_since(t0);
  report.storage_relative_error = norm2 > 0 ? std::sqrt(error2 / norm2) : 0.0;
  return report;
}

}  // namespace matlas
