#include "gp/sparse_optimize.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/check.h"
#include "core/error.h"
#include "gp/coarse_placement.h"
#include "gp/initialize.h"
#include "gp/lbfgs_driver.h"
#include "gp/optimize_run.h"

namespace matlas::gp {

namespace {

using detail::StopRequested;

/// The bookkeeping of one start: -l and its gradient for LBFGSpp over x = [vec X; vec Z], the best
/// point, the history, progress lines and the limits (as detail::OptimizationRun does for the
/// exact likelihood).
class SparseRun {
public:
  /// tied: the inducing points are the rows `tied` of X (moved with them); else Z0 is free.
  SparseRun(SparseLikelihoodEvaluator& evaluator, const Eigen::MatrixXd& X0, const Eigen::MatrixXd& Z0,
            std::vector<Eigen::Index> tied, const OptimizeOptions& o, ProgressSink& sink)
      : evaluator_(evaluator), options_(o), sink_(sink), tied_(std::move(tied)), n_(X0.rows()),
        m_(tied_.empty() ? Z0.rows() : static_cast<Eigen::Index>(tied_.size())), q_(X0.cols()) {
    best_.resize((tied_.empty() ? n_ + m_ : n_) * q_);
    best_.head(n_ * q_) = Eigen::Map<const Eigen::VectorXd>(X0.data(), X0.size());
    if (tied_.empty()) best_.tail(m_ * q_) = Eigen::Map<const Eigen::VectorXd>(Z0.data(), Z0.size());
    best_value_ = evaluator_.normalized(X0, inducing(best_));
    initial_value_ = best_value_;
    evaluations_ = 1;
    history_.push_back(best_value_);
    report(true);
  }

  Eigen::MatrixXd latent(const Eigen::VectorXd& x) const { return Eigen::Map<const Eigen::MatrixXd>(x.data(), n_, q_); }
  Eigen::MatrixXd inducing(const Eigen::VectorXd& x) const {
    if (tied_.empty()) return Eigen::Map<const Eigen::MatrixXd>(x.data() + n_ * q_, m_, q_);
    const Eigen::Map<const Eigen::MatrixXd> X(x.data(), n_, q_);
    Eigen::MatrixXd Z(m_, q_);
    for (Eigen::Index k = 0; k < m_; ++k) Z.row(k) = X.row(tied_[static_cast<std::size_t>(k)]);
    return Z;
  }
  const Eigen::VectorXd& best_point() const { return best_; }
  double best_value() const { return best_value_; }
  double initial_value() const { return initial_value_; }

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& grad) {
    if (options_.time_limit_seconds > 0 && elapsed() > options_.time_limit_seconds) throw StopRequested{"time limit reached"};
    const double value = evaluator_.normalized(latent(x), inducing(x), &gX_, &gZ_);
    ++evaluations_;
    grad.resize(x.size());
    if (tied_.empty()) {
      grad << -Eigen::Map<const Eigen::VectorXd>(gX_.data(), gX_.size()),
          -Eigen::Map<const Eigen::VectorXd>(gZ_.data(), gZ_.size());
    } else {  // an inducing point moves with its latent point
      for (Eigen::Index k = 0; k < m_; ++k) gX_.row(tied_[static_cast<std::size_t>(k)]) += gZ_.row(k);
      grad = -Eigen::Map<const Eigen::VectorXd>(gX_.data(), gX_.size());
    }
    if (value > best_value_) {
      best_value_ = value;
      best_ = x;
      if (evaluator_.to_log_likelihood(best_value_) >= options_.target_value) {
        history_.push_back(best_value_);
        throw StopRequested{"target value reached"};
      }
    }
    return -value;
  }

  void end_iteration() {
    ++iterations_;
    history_.push_back(best_value_);
    report(false);
    if (iterations_ >= options_.max_iterations) throw StopRequested{"iteration limit reached"};
    constexpr int kWindow = 3;
    if (iterations_ >= kWindow) {
      const double before = history_[history_.size() - 1 - kWindow];
      if (best_value_ - before <= options_.tolerance * std::max(1.0, std::abs(best_value_)))
        throw StopRequested{"converged: relative improvement below tolerance"};
    }
  }

  OptimizeResult finish(std::string reason, Eigen::MatrixXd* Z) {
    OptimizeResult r;
    r.latent = latent(best_);
    if (Z != nullptr) *Z = inducing(best_);
    r.value = evaluator_.to_log_likelihood(best_value_);
    r.iterations = iterations_;
    r.evaluations = evaluations_;
    r.seconds = elapsed();
    for (double v : history_) r.history.push_back(evaluator_.to_log_likelihood(v));
    r.stop_reason = std::move(reason);
    report(true);
    sink_.message("sparse lbfgs stopped: " + r.stop_reason);
    return r;
  }

private:
  double elapsed() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void report(bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && now - last_report_ < std::chrono::milliseconds(250)) return;
    last_report_ = now;
    char line[160];
    std::snprintf(line, sizeof line, "sparse lbfgs iter %d  L~ = %.10g  (evaluations %d, %.2f s)", iterations_,
                  evaluator_.to_log_likelihood(best_value_), evaluations_, elapsed());
    sink_.message(line);
  }

  SparseLikelihoodEvaluator& evaluator_;
  const OptimizeOptions& options_;
  ProgressSink& sink_;
  std::vector<Eigen::Index> tied_;
  Eigen::Index n_, m_, q_;
  Eigen::VectorXd best_;
  Eigen::MatrixXd gX_, gZ_;
  double best_value_ = 0, initial_value_ = 0;
  int iterations_ = 0, evaluations_ = 0;
  std::vector<double> history_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_report_{};
};

std::string run_sparse_lbfgs(SparseRun& run, const OptimizeOptions& o) {
  return detail::run_restarting_lbfgs(run, o.tolerance, run.initial_value());
}

Eigen::MatrixXd gather_rows(const Eigen::MatrixXd& X, const std::vector<Eigen::Index>& rows) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(rows.size()), X.cols());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    MATLAS_CHECK(rows[k] >= 0 && rows[k] < X.rows(), "a chosen row of X");
    out.row(static_cast<Eigen::Index>(k)) = X.row(rows[k]);
  }
  return out;
}

/// Scale factor of start k, as optimize_latent's: 1, 2^-1/2, 2^1/2, 2^-1, 2^1, ...
double sparse_start_scale(int k) {
  if (k == 0) return 1.0;
  const double exponent = 0.5 * ((k + 1) / 2);
  return std::exp2(k % 2 == 1 ? -exponent : exponent);
}

/// optimize_sparse_latent with a coarse stage (s.coarse in (0, n)): the starts on the subset, the
/// interpolation of the others, one refinement of all.
OptimizeResult coarse_to_fine(const SparseProblem& p, const Eigen::MatrixXd& X0, const SparseOptions& s,
                              const OptimizeOptions& o, ProgressSink& sink, Eigen::MatrixXd* inducing_out) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Eigen::Index> rows = coarse_subset(X0.rows(), s.coarse);
  SparseOptions one_stage = s;
  one_stage.coarse = 0;
  one_stage.inducing = std::min(s.inducing, s.coarse);
  sink.message("coarse placement: " + std::to_string(rows.size()) + " of " + std::to_string(X0.rows()) + " items");
  OptimizeOptions first = o;  // the target is the whole problem's: not for the subset's objective
  first.target_value = std::numeric_limits<double>::infinity();
  const OptimizeResult coarse =
      optimize_sparse_latent(subset_problem(p, rows), gather_rows(X0, rows), one_stage, first, sink);
  // The interpolated layout about its centroid, scaled to the whole problem's best (n items
  // spread wider than the subset's c: their repulsion and covariance want room).
  Eigen::MatrixXd X1 = interpolate_layout(p.data, rows, coarse.latent);
  X1 = X1.rowwise() - X1.colwise().mean();
  if (X1.norm() > 0) {  // else a degenerate subset layout: nothing to scale
    SparseLikelihoodEvaluator evaluator(p);
    const std::vector<Eigen::Index> chosen = farthest_point_indices(X1, s.inducing);
    const Eigen::MatrixXd Z = gather_rows(X1, chosen);
    evaluator.set_blocks(local_blocks(X1, Z, s.block));
    const double a = best_scale_factor(
        [&](const Eigen::MatrixXd& aX) { return evaluator.normalized(aX, aX.norm() / X1.norm() * Z); }, X1, 0.25, 4.0);
    sink.message("coarse placement: the others interpolated, the layout scaled by " + std::to_string(a));
    X1 *= a;
  }
  sink.message("refinement of all " + std::to_string(X0.rows()) + " items");
  one_stage.inducing = s.inducing;
  return with_coarse_stage(
      optimize_sparse_latent(p, X1, one_stage, refinement_options(o, coarse.seconds), sink, inducing_out), coarse, start);
}

}  // namespace

std::vector<std::vector<Eigen::Index>> local_blocks(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, int max_block) {
  if (max_block < 1) throw Error("sparse blocks: the block size must be >= 1");
  if (Z.rows() == 0 || Z.cols() != X.cols()) throw Error("sparse blocks: need inducing points of the latent dimension");
  std::vector<std::vector<Eigen::Index>> cells(static_cast<std::size_t>(Z.rows()));
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    Eigen::Index nearest = 0;
    (Z.rowwise() - X.row(i)).rowwise().squaredNorm().minCoeff(&nearest);
    cells[static_cast<std::size_t>(nearest)].push_back(i);
  }
  std::vector<std::vector<Eigen::Index>> blocks;
  for (std::vector<Eigen::Index>& cell : cells) {
    if (cell.empty()) continue;
    std::stable_sort(cell.begin(), cell.end(), [&](Eigen::Index a, Eigen::Index b) { return X(a, 0) < X(b, 0); });
    const std::size_t size = static_cast<std::size_t>(max_block);
    const std::size_t runs = (cell.size() + size - 1) / size;
    for (std::size_t r = 0; r < runs; ++r) {  // runs of equal length, not a full run and a remnant
      const std::size_t begin = r * cell.size() / runs, end = (r + 1) * cell.size() / runs;
      blocks.emplace_back(cell.begin() + static_cast<std::ptrdiff_t>(begin), cell.begin() + static_cast<std::ptrdiff_t>(end));
    }
  }
  std::size_t assigned = 0;
  for (const auto& b : blocks) assigned += b.size();
  MATLAS_CHECK_EQ(assigned, static_cast<std::size_t>(X.rows()));  // every item in exactly one block
  return blocks;
}

int automatic_coarse(Eigen::Index n) { return n >= 2000 ? static_cast<int>(n / 10) : 0; }

SparseProblem sparse_problem(const LikelihoodProblem& p, int rank) {
  SparseProblem s;
  s.data = low_rank_gram(p.gram, rank);
  s.columns = p.columns;
  s.kernel = p.kernel;
  s.prior = p.prior;
  return s;
}

Eigen::MatrixXd sparse_pca_initialization(const SparseProblem& p, int q, int inducing, int block) {
  SparseLikelihoodEvaluator evaluator(p);  // validates the problem
  if (q < 1) throw Error("sparse_pca_initialization: latent dimension must be >= 1 (got " + std::to_string(q) + ")");
  if (inducing < 1) throw Error("sparse_pca_initialization: need at least one inducing point");
  const Eigen::MatrixXd& Y = p.data.factor;
  const Eigen::Index n = Y.rows();
  // The factor's columns are orthogonal; order them by norm (the eigenvalues) to be safe.
  std::vector<Eigen::Index> cols(static_cast<std::size_t>(Y.cols()));
  for (Eigen::Index c = 0; c < Y.cols(); ++c) cols[static_cast<std::size_t>(c)] = c;
  std::stable_sort(cols.begin(), cols.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return Y.col(a).squaredNorm() > Y.col(b).squaredNorm(); });
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, q);
  for (Eigen::Index k = 0; k < std::min<Eigen::Index>(q, Y.cols()); ++k) {
    Eigen::VectorXd u = Y.col(cols[static_cast<std::size_t>(k)]) / std::sqrt(evaluator.scale());
    Eigen::Index imax = 0;
    u.cwiseAbs().maxCoeff(&imax);
    if (u[imax] < 0) u = -u;
    X.col(k) = u;
  }
  const double rms = std::sqrt(X.squaredNorm() / static_cast<double>(n));
  if (!(rms > 0)) return X;
  const Eigen::MatrixXd Z = farthest_point_subset(X, inducing);  // scales with X
  evaluator.set_blocks(local_blocks(X, Z, block));
  const auto value = [&](const Eigen::MatrixXd& aX) {
    const double a = aX.norm() / X.norm();
    return evaluator.normalized(aX, a * Z);
  };
  const double unit = p.kernel.lengthscale / rms;
  return best_scale_factor(value, X, unit * 1e-3, unit * 1e3) * X;
}

OptimizeResult optimize_sparse_latent(const SparseProblem& p, const Eigen::MatrixXd& X0, const SparseOptions& s,
                                      const OptimizeOptions& o, ProgressSink& sink, Eigen::MatrixXd* inducing_out) {
  const int inducing = s.inducing;
  if (o.method != Optimizer::lbfgs) throw Error("the sparse latent optimisation runs L-BFGS only");
  if (inducing < 1) throw Error("optimize_sparse_latent: need at least one inducing point");
  if (!X0.allFinite() || X0.cols() == 0) throw Error("optimize_sparse_latent: X0 must be finite with q >= 1");
  if (o.starts < 1) throw Error("optimize_sparse_latent: starts must be >= 1");
  if (!(o.tolerance >= 0) || o.max_iterations < 0 || !(o.time_limit_seconds >= 0))
    throw Error("optimize_sparse_latent: tolerance, max_iterations and time_limit_seconds must be >= 0");
  if (s.coarse < -1) throw Error("optimize_sparse_latent: the coarse subset's size must be >= 0 (or -1: automatic)");
  SparseLikelihoodEvaluator evaluator(p);
  if (X0.rows() != evaluator.count())
    throw Error("optimize_sparse_latent: X0 has " + std::to_string(X0.rows()) + " rows for " +
                std::to_string(evaluator.count()) + " items");
  const int coarse = s.coarse < 0 ? automatic_coarse(X0.rows()) : s.coarse;
  if (coarse > 0 && coarse < X0.rows()) {
    SparseOptions staged = s;
    staged.coarse = coarse;
    return coarse_to_fine(p, X0, staged, o, sink, inducing_out);
  }
  detail::BestOfStarts starts(o);
  const Eigen::RowVectorXd centroid = X0.colwise().mean();
  Eigen::MatrixXd best_Z;
  for (int k = 0; k < o.starts && !starts.done(); ++k) {
    const std::optional<OptimizeOptions> one = starts.start(k);
    if (!one) break;
    if (o.starts > 1) sink.message("start " + std::to_string(k + 1) + "/" + std::to_string(o.starts));
    const Eigen::MatrixXd Xk = (sparse_start_scale(k) * (X0.rowwise() - centroid)).rowwise() + centroid;
    std::vector<Eigen::Index> chosen = farthest_point_indices(Xk, inducing);
    Eigen::MatrixXd Z0;
    if (s.free_inducing) {
      Z0.resize(static_cast<Eigen::Index>(chosen.size()), Xk.cols());
      for (std::size_t j = 0; j < chosen.size(); ++j) Z0.row(static_cast<Eigen::Index>(j)) = Xk.row(chosen[j]);
      chosen.clear();
    }
    evaluator.set_blocks(local_blocks(Xk, s.free_inducing ? Z0 : gather_rows(Xk, chosen), s.block));
    SparseRun run(evaluator, Xk, Z0, std::move(chosen), *one, sink);
    Eigen::MatrixXd Z;
    std::string reason;
    if (evaluator.to_log_likelihood(run.best_value()) >= o.target_value) reason = "target value reached";
    else if (o.max_iterations == 0) reason = "iteration limit reached";
    else reason = run_sparse_lbfgs(run, *one);
    if (starts.add(run.finish(reason, &Z), k)) best_Z = std::move(Z);
  }
  if (inducing_out != nullptr) *inducing_out = std::move(best_Z);
  return starts.finish();
}

}  // namespace matlas::gp
