#include "manifold/build.h"

#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <iomanip>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "brdf/albedo.h"
#include "core/atomic_file.h"
#include "core/check.h"
#include "core/error.h"
#include "core/file_io.h"
#include "core/hash.h"
#include "formats/safetensors.h"
#include "gp/initialize.h"
#include "gp/likelihood.h"
#include "gp/posterior.h"
#include "manifold/column_blocks.h"
#include "manifold/data_shares.h"
#include "manifold/data_writer.h"
#include "manifold/gram_reduce.h"
#include "manifold/model_format.h"

namespace matlas {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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
  if (!(o.convex_ridge > 0.0) || !std::isfinite(o.convex_ridge))
    throw Error("--convex-ridge must be finite and > 0, got " + std::to_string(o.convex_ridge));
  if (o.optimize.coarse < -1)
    throw Error("--coarse must be >= 0 (or -1: automatic), got " + std::to_string(o.optimize.coarse));
  if (o.optimize.max_iterations < -1)
    throw Error("--max-iterations must be >= 0 (or -1: automatic), got " + std::to_string(o.optimize.max_iterations));
  if (o.optimize.coarse > 0 && o.sparse.enabled())
    throw Error("--coarse is the exact placement's; with --sparse-inducing, --sparse-coarse sets the sparse one's");
  if (o.sparse.inducing < 0 || o.sparse.coarse < -1 || (o.sparse.enabled() && (o.sparse.rank < 1 || o.sparse.block < 1)))
    throw Error("--sparse-inducing must be >= 0, --sparse-coarse >= -1, --sparse-rank and --sparse-block >= 1");
  if (o.sparse.enabled() && o.optimize.method != gp::Optimizer::lbfgs)
    throw Error("--sparse-inducing needs the lbfgs optimizer");
  const MerlDims& g = set.dims();
  if (!model_format::is_model_grid(g.theta_h, g.theta_d, g.phi_d))
    throw file_error(set.file(0).path(), "grid " + g.to_string() +
                                             ": a model needs phi_d = 2 theta_d (theta_d over [0, 90) and phi_d over "
                                             "[0, 180) degrees in equal steps, as MERL's 90 90 180)");
  if (static_cast<std::size_t>(o.dim) >= set.size())
    throw Error("--dim " + std::to_string(o.dim) + " needs more than " + std::to_string(o.dim) +
                " materials; the input has " + std::to_string(set.size()));
}

/// The output must not be one of the inputs (writing the model would replace a material, or a
/// symlink or hard link to it): core/file_io.h compares the files themselves.
void reject_output_among_inputs(const MaterialSet& set, const fs::path& output) {
  std::error_code ec;
  if (fs::is_directory(output, ec))
    throw file_error(output, "the output is a folder; give a file name such as model.matlas");
  std::vector<fs::path> inputs;
  for (std::size_t i = 0; i < set.size(); ++i) inputs.push_back(set.file(i).path());
  refuse_output_among_inputs(output, inputs);
}

/// Identical (or numerically identical) materials make K singular in the limit and the layout
/// meaningless: refuse them with the names. A pair is identical when its squared distance is at
/// most 1e-12 of the mean squared norm in both the linear Gram s and the layout's Gram t (the same
/// matrix for the linear layout). The linear scale alone is set by the database's brightest
/// materials: with sharp conductors among a thousand materials, a diffuse material and a mixture
/// of it with 16 % of two others fell under it; in the layout's (cube-root, cosine) space they do not.
void reject_duplicates(const MaterialSet& set, const Eigen::MatrixXd& s, const Eigen::MatrixXd& t) {
  // Values are bounded when read (kMaxMerlMagnitude), so this cannot overflow; if it ever does, it
  // must not pass for "identical" (NaN compares false) or give a meaningless layout.
  for (Eigen::Index i = 0; i < s.rows(); ++i)
    if (!s.row(i).allFinite() || !t.row(i).allFinite())
      throw file_error(set.file(static_cast<std::size_t>(i)).path(),
                       "its values overflow the sums of squares (non-finite Gram matrix): the file holds absurd values");
  const double scale = s.diagonal().mean();
  if (!(scale > 0.0)) throw Error("all input materials are identical: nothing to map");
  const double layout_scale = t.diagonal().mean();
  const auto close = [](const Eigen::MatrixXd& g, Eigen::Index i, Eigen::Index j, double of) {
    return g(i, i) + g(j, j) - 2.0 * g(i, j) <= 1e-12 * of;
  };
  for (Eigen::Index i = 0; i < s.rows(); ++i)
    for (Eigen::Index j = i + 1; j < s.rows(); ++j) {
      if (close(s, i, j, scale) && close(t, i, j, layout_scale))
        throw Error("materials '" + set.name(static_cast<std::size_t>(i)) + "' and '" +
                    set.name(static_cast<std::size_t>(j)) +
                    "' are identical (duplicate files?): remove one of them");
    }
}

/// The exact placement's coarse subset for n items as the model records it (0: all at once).
int exact_coarse(const gp::OptimizeOptions& o, Eigen::Index n) {
  const int coarse = o.resolved(n).coarse;
  return coarse < n ? coarse : 0;
}

/// The model metadata with everything known before the pass; the rest is filled in at the end.
json model_metadata_skeleton(const MaterialSet& set, const BuildOptions& options, DType storage) {
  json sources = json::array();
  for (std::size_t i = 0; i < set.size(); ++i)
    sources.push_back({{"name", set.name(i)},
                       {"file", set.file(i).path().filename().string()},
                       {"path", fs::absolute(set.file(i).path()).string()},
                       {"xxh3_64", hex64(0)}});
  return {
      {"format", model_format::kFormatName},
      {"format_version", model_format::kVersion},
      {"matlas_version", MATLAS_VERSION},
      {"created", utc_now()},
      {"names", set.names()},
      {"count", set.size()},
      {"dim", options.dim},
      {"grid", {set.dims().theta_h, set.dims().theta_d, set.dims().phi_d}},
      {"kernel", {{"type", "squared-exponential"}, {"lengthscale", 1.0}, {"nugget", options.nugget}}},
      {"data_layout",
       "data[c, i] = z_i[v] for the kept column c of value index v (value_column[v] = c; "
       "v = channel * bins + bin; physical units); m(x)[v] = (1 - sum w) mean[c] + sum_i w_i data[c, i]"},
      {"storage", dtype_name(storage)},
      {"layout_transform", options.layout.to_string()},
      {"latent_prior",
       {{"repulsion", options.prior.repulsion},
        {"radius", options.prior.radius},
        {"precision", options.prior.precision},
        {"complexity_weight", options.prior.complexity_weight}}},
      {"interpolation", {{"mode", to_string(options.interpolation)}, {"ridge", options.convex_ridge}}},
      {"latent_optimization",
       options.sparse.enabled()
           ? json{{"method", "sparse"},
                  {"inducing", options.sparse.inducing},
                  {"rank", options.sparse.rank},
                  {"block", options.sparse.block},
                  {"coarse", options.sparse.coarse >= 0 ? options.sparse.coarse
                                                        : gp::automatic_coarse(static_cast<Eigen::Index>(set.size()))}}
           : json{{"method", "exact"},
                  {"coarse", exact_coarse(options.optimize, static_cast<Eigen::Index>(set.size()))}}},
      {"albedo", albedo_rule_description()},
      {"sources", sources},
  };
}

/// Header bytes to reserve: the skeleton plus generous room for what the build adds (numbers,
/// the optimiser's report, the tensor table), so that the header always fits.
std::size_t header_reserve(const json& skeleton) {
  return skeleton.dump().size() * 2 + 16384;
}

/// The value-index -> kept-column map.
std::vector<std::int32_t> column_map(const std::vector<bool>& kept) {
  std::vector<std::int32_t> map(kept.size(), -1);
  std::int32_t next = 0;
  for (std::size_t v = 0; v < kept.size(); ++v)
    if (kept[v]) map[v] = next++;
  return map;
}

/// A distributed build's slices of the model (data_shares.h): rank 0 tells the others the model's
/// temporary file, where rank 1's data starts and where value_column starts; rank r > 0 copies
/// its data after the data of ranks 1..r-1; every rank writes its means and its part of the
/// value-to-column map. Rank 0 counts what the others write as written.
void place_slices(SafetensorsWriter& writer, AtomicFile* share_file, const GramResult& g,
                  const std::vector<std::uint64_t>& kept_per_rank, std::size_t column_bytes, Communicator& comm) {
  std::string place;  // "DATA_OFFSET VALUE_COLUMN_OFFSET PATH" on rank 0
  if (comm.is_root())
    place = std::to_string(writer.append_offset()) + " " + std::to_string(writer.tensor_offset(model_format::kValueColumn)) +
            " " + writer.temporary().string();
  comm.broadcast(place);
  run_collectively(comm, [&] {
    std::istringstream in(place);
    std::uint64_t offset = 0, value_column = 0;
    in >> offset >> value_column;
    in.get();
    std::string path;
    std::getline(in, path);
    MATLAS_CHECK(!in.fail() && !path.empty(), "the model's temporary file and offsets");
    const fs::path model = path;
    const auto rank = static_cast<std::size_t>(comm.rank());
    std::uint64_t kept_before = 0, others = 0;
    for (std::size_t r = 0; r < kept_per_rank.size(); ++r) {
      if (r < rank) kept_before += kept_per_rank[r];
      if (r == 0) continue;  // rank 0's data is in place (appended during the pass)
      const std::uint64_t bytes = kept_per_rank[r] * column_bytes;
      if (r == rank) copy_share_into(share_file->temporary(), bytes, model, offset);
      offset += bytes;
      others += bytes;
    }
    // After the data, the mean: float32 per kept column, this rank's after the ranks before it.
    const std::uint64_t mean_offset = offset + kept_before * 4u;
    const Eigen::VectorXf mean_f = g.mean.cast<float>();
    if (mean_f.size() > 0) write_into(model, mean_offset, mean_f.data(), static_cast<std::size_t>(mean_f.size()) * 4u);
    std::vector<std::int32_t> columns(g.end_value - g.first_value, -1);
    auto next = static_cast<std::int32_t>(kept_before);
    for (std::size_t v = g.first_value; v < g.end_value; ++v)
      if (g.kept[v]) columns[v - g.first_value] = next++;
    if (!columns.empty())
      write_into(model, value_column + g.first_value * 4u, columns.data(), columns.size() * 4u);
    if (comm.is_root()) {
      writer.skip(others);
      writer.end_growing();
      writer.skip(g.kept_columns * 4u);
      writer.end_growing();
      writer.written_elsewhere(model_format::kValueColumn);
    }
  });
}

}  // namespace

gp::OptimizeResult place_latent_points(const gp::LikelihoodProblem& problem, int q, const gp::OptimizeOptions& optimize,
                                       const gp::SparseOptions& sparse, ProgressSink& progress) {
  if (sparse.enabled() && optimize.method != gp::Optimizer::lbfgs)
    throw Error("the sparse latent optimisation (--sparse-inducing) needs the lbfgs optimizer");
  if (sparse.enabled()) {
    const gp::SparseProblem p = gp::sparse_problem(problem, sparse.rank);
    const Eigen::MatrixXd x0 = gp::sparse_pca_initialization(p, q, sparse.inducing, sparse.block);
    gp::OptimizeOptions o = optimize;
    if (o.max_iterations == -1) o.max_iterations = gp::OptimizeOptions{}.max_iterations;  // automatic: the exact one's rule is for O(n^3)
    return gp::optimize_sparse_latent(p, x0, sparse, o, progress);
  }
  // A coarse-to-fine placement scales its subset itself: the PCA start's own search is skipped.
  // The Gram's factor (an eigen-decomposition) is computed once for the start and the placement.
  const Eigen::Index n = problem.gram.rows();
  const gp::OptimizeOptions resolved = optimize.resolved(n);
  const bool coarse = resolved.coarse > 0 && resolved.coarse < n;
  const gp::LikelihoodProblem shared = gp::with_factor(problem);
  return gp::optimize_latent(shared, gp::pca_initialization(shared, q, !coarse), resolved, progress);
}

namespace {

/// The latent placement: MAP optimisation of the GP likelihood over the layout Gram matrix (sparse
/// when options.sparse is on), from PCA; the result and its figures go into `report`.
void place_latent(const BuildOptions& options, const GramResult& g, BuildReport& report, ProgressSink& progress) {
  const int q = options.dim;
  gp::LikelihoodProblem problem;
  problem.gram = g.layout_gram;
  problem.columns = static_cast<double>(g.kept_columns);
  problem.kernel = gp::Kernel{1.0, options.nugget};
  problem.prior = options.prior;
  report.optimization =
      place_latent_points(problem, q, BuildOptions::resolved(options.optimize, q), options.sparse, progress);
  report.log_likelihood = report.optimization.value;
  // Constructing the posterior checks that K is positive definite (matlas::Error otherwise).
  [[maybe_unused]] const gp::GpPosterior posterior(report.optimization.latent, problem.kernel);
}

/// Writes the small tensors (latent, Gram matrices, albedo, and the column map when this process
/// made it) and returns their checksum, with the mean (`mean_f`, read back from the file when the
/// ranks placed it: `slices_placed`).
std::uint64_t write_small_tensors(const MaterialSet& set, const GramResult& g, const BuildReport& report,
                                  SafetensorsWriter& writer, bool slices_placed, Eigen::VectorXf& mean_f) {
  std::vector<std::int32_t> columns;
  if (slices_placed) {  // read back for the checksum
    const auto mean_bytes = read_from(writer.temporary(), writer.tensor_offset(model_format::kMean), g.kept_columns * 4u);
    mean_f.resize(static_cast<Eigen::Index>(g.kept_columns));
    std::memcpy(mean_f.data(), mean_bytes.data(), mean_bytes.size());
    const auto column_bytes = read_from(writer.temporary(), writer.tensor_offset(model_format::kValueColumn),
                                        set.value_count() * 4u);
    columns.resize(set.value_count());
    std::memcpy(columns.data(), column_bytes.data(), column_bytes.size());
  } else {
    columns = column_map(g.kept);
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor latent_rows = report.optimization.latent;
  const RowMajor gram_rows = g.gram;
  const RowMajor layout_gram_rows = g.layout_gram;
  const RowMajor albedo_rows = g.albedo;
  writer.write_tensor(model_format::kLatent, latent_rows.data(), static_cast<std::size_t>(latent_rows.size()) * 8u);
  writer.write_tensor(model_format::kGram, gram_rows.data(), static_cast<std::size_t>(gram_rows.size()) * 8u);
  writer.write_tensor(model_format::kLayoutGram, layout_gram_rows.data(),
                      static_cast<std::size_t>(layout_gram_rows.size()) * 8u);
  writer.write_tensor(model_format::kAlbedo, albedo_rows.data(), static_cast<std::size_t>(albedo_rows.size()) * 8u);
  if (!slices_placed) writer.write_tensor(model_format::kValueColumn, columns.data(), columns.size() * 4u);

  Xxh3Hasher small_hash;
  for (const auto& [ptr, bytes] :
       {std::pair<const void*, std::size_t>{latent_rows.data(), latent_rows.size() * 8u},
        {gram_rows.data(), gram_rows.size() * 8u},
        {albedo_rows.data(), albedo_rows.size() * 8u},
        {mean_f.data(), mean_f.size() * 4u},
        {columns.data(), columns.size() * 4u},
        {layout_gram_rows.data(), layout_gram_rows.size() * 8u}})
    small_hash.update(ptr, bytes);
  return small_hash.digest();
}

/// Rank 0's rest of a build after the pass: the mean, the latent placement, the small tensors and
/// the metadata, then commit.
void finish_model(const MaterialSet& set, const BuildOptions& options, const GramResult& g,
                  SafetensorsWriter& writer, json& meta, BuildReport& report,
                  std::chrono::steady_clock::time_point t0, ProgressSink& progress, int ranks) {
  const bool slices_placed = ranks > 1;  // mean and value_column written by the ranks (place_slices)
  Eigen::VectorXf mean_f;
  if (!slices_placed) {
    writer.end_growing();
    mean_f = g.mean.cast<float>();
    writer.append(mean_f.data(), static_cast<std::size_t>(mean_f.size()) * 4u);
    writer.end_growing();
  }
  report.pass_seconds = seconds_since(t0);
  reject_duplicates(set, g.gram, g.layout_gram);
  progress.message("kept " + std::to_string(g.kept_columns) + " of " +
                   std::to_string(set.value_count()) + " columns (" +
                   std::to_string(report.dropped_columns) +
                   " dropped: not measured in every material)");

  t0 = std::chrono::steady_clock::now();
  place_latent(options, g, report, progress);
  report.optimize_seconds = seconds_since(t0);

  // The small tensors, the metadata, then commit (the data went to disk during the pass, with
  // direct I/O where the file system has it).
  t0 = std::chrono::steady_clock::now();
  const std::uint64_t small_checksum = write_small_tensors(set, g, report, writer, slices_placed, mean_f);

  for (std::size_t i = 0; i < set.size(); ++i) {
    if (ranks == 1) {
      meta["sources"][i]["xxh3_64"] = hex64(g.hashes[i]);
    } else {  // no rank read the whole file: the hash of the ranks' hashes of their byte ranges
      meta["sources"][i].erase("xxh3_64");
      meta["sources"][i]["xxh3_64_of_parts"] = hex64(g.hashes[i]);
    }
  }
  if (ranks > 1)
    meta["distributed"] = {{"ranks", ranks}, {"block_columns", resolved_block_columns(options.block_columns, set.size())}};
  meta["log_likelihood"] = report.log_likelihood;
  meta["optimizer"] = {{"method", gp::to_string(options.optimize.method)},
                       {"iterations", report.optimization.iterations},
                       {"evaluations", report.optimization.evaluations},
                       {"seconds", report.optimization.seconds},
                       {"stop_reason", report.optimization.stop_reason},
                       {"converged", report.optimization.converged()}};
  meta["kept_columns"] = g.kept_columns;
  meta["dropped_columns"] = report.dropped_columns;
  meta["small_tensors_xxh3_64"] = hex64(small_checksum);
  writer.add_metadata(model_format::kMetadataKey, meta.dump());
  writer.commit();
  report.finish_seconds = seconds_since(t0);
}

}  // namespace

BuildOptions BuildOptions::paper_preset() {
  BuildOptions o;
  o.nugget = 1e-4;
  o.layout = LayoutTransform{LayoutTransform::Map::linear, false};
  o.prior = gp::LatentPrior{};
  o.optimize.method = gp::Optimizer::hooke_jeeves;
  o.optimize.starts = 1;
  o.optimize.max_iterations = gp::OptimizeOptions{}.max_iterations;  // all at once, 5000 sweeps at any size
  o.optimize.coarse = 0;
  o.interpolation = Interpolation::gp;
  return o;
}

BuildReport build_model(const MaterialSet& set, const BuildOptions& options, const fs::path& output,
                        ProgressSink& progress, Communicator& comm) {
  const bool root = comm.is_root(), split = comm.size() > 1;
  BuildReport report;
  const auto n = static_cast<Eigen::Index>(set.size());
  const int q = options.dim;
  const DType storage = options.storage == Storage::f16 ? DType::F16 : DType::F32;

  // The model file: fixed-size tensors first (written at the end), then the data and the mean,
  // whose sizes are known after the pass. The header is written last, into reserved space.
  SafetensorsWriter writer;
  writer.declare(model_format::kLatent, DType::F64, {n, q});
  writer.declare(model_format::kGram, DType::F64, {n, n});
  writer.declare(model_format::kLayoutGram, DType::F64, {n, n});
  writer.declare(model_format::kAlbedo, DType::F64, {n, kAlbedoAngles, 3});
  writer.declare(model_format::kValueColumn, DType::I32, {static_cast<std::int64_t>(set.value_count())});
  writer.declare_growing(model_format::kData, storage, {n});
  writer.declare_growing(model_format::kMean, DType::F32, {});

  // One pass: mask, mean, Gram matrices, albedo curves, hashes, and the data written as it goes
  // (rank 0's share into the model, another rank's into a file of its own, data_shares.h).
  auto t0 = std::chrono::steady_clock::now();
  json meta = model_metadata_skeleton(set, options, storage);
  std::unique_ptr<AtomicFile> share_file;
  std::unique_ptr<DataWriter> data;
  run_collectively(comm, [&] {
    validate(set, options);
    reject_output_among_inputs(set, output);
    if (root) {
      writer.begin(output, header_reserve(meta));
      data = std::make_unique<DataWriter>(writer, set.size(), storage);
    } else {
      share_file = std::make_unique<AtomicFile>(data_share_path(output, comm.rank()));
      data = std::make_unique<DataWriter>(
          [file = share_file.get()](const void* bytes, std::size_t count) { file->write(bytes, count); }, set.size(),
          storage);
    }
  });
  GramResult g;
  auto lap = std::chrono::steady_clock::now();
  const auto since_lap = [&lap] {
    const double seconds = seconds_since(lap);
    lap = std::chrono::steady_clock::now();
    return seconds;
  };
  run_collectively(comm, [&] {
    g = accumulate_gram(set, options.layout, options.block_columns, progress, data.get(), {comm.rank(), comm.size()});
    report.share_seconds = since_lap();
  });
  report.wait_seconds = since_lap();
  std::vector<std::uint64_t> kept_per_rank;
  run_collectively(comm, [&] { kept_per_rank = reduce_gram(g, !options.layout.is_identity(), comm); });
  auto [error2, norm2] = data->error_sums();
  if (split) {
    std::array<double, 2> sums{error2, norm2};
    comm.sum(sums);
    error2 = sums[0];
    norm2 = sums[1];
    report.reduce_seconds = since_lap();
    place_slices(writer, share_file.get(), g, kept_per_rank, set.size() * dtype_size(storage), comm);
    report.place_seconds = since_lap();
  }
  report.storage_relative_error = norm2 > 0 ? std::sqrt(error2 / norm2) : 0.0;
  report.kept_columns = g.kept_columns;
  report.dropped_columns = set.value_count() - g.kept_columns;
  report.pass_steps = g.steps;
  if (!root) {  // rank 0 places the latent points and writes the rest; the others wait for it
    run_collectively(comm, [] {});
    report.pass_seconds = seconds_since(t0);
    return report;
  }
  run_collectively(comm, [&] { finish_model(set, options, g, writer, meta, report, t0, progress, comm.size()); });
  return report;
}

}  // namespace matlas
