#include "eval/fit_records.h"

#include "core/check.h"

namespace matlas::eval {

namespace {

void append(std::vector<double>& out, const Eigen::VectorXd& v) {
  out.push_back(static_cast<double>(v.size()));
  out.insert(out.end(), v.data(), v.data() + v.size());
}

/// Reads a record front to back, checking that it holds what is asked.
class Reader {
public:
  explicit Reader(std::span<const double> record) : record_(record) {}
  double next() {
    MATLAS_CHECK_LT(at_, record_.size());
    return record_[at_++];
  }
  std::span<const double> next(std::size_t count) {
    MATLAS_CHECK_LE(at_ + count, record_.size());
    const auto span = record_.subspan(at_, count);
    at_ += count;
    return span;
  }
  Eigen::VectorXd vector() {
    const auto values = next(static_cast<std::size_t>(next()));
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  }
  void end() const { MATLAS_CHECK_EQ(at_, record_.size()); }

private:
  std::span<const double> record_;
  std::size_t at_ = 0;
};

}  // namespace

std::vector<double> fit_record(double seconds, double log_likelihood, const Eigen::MatrixXd& latent) {
  std::vector<double> out{seconds, log_likelihood, static_cast<double>(latent.rows()),
                          static_cast<double>(latent.cols())};
  out.insert(out.end(), latent.data(), latent.data() + latent.size());
  return out;
}

void read_fit_record(std::span<const double> record, double& seconds, double& log_likelihood, Eigen::MatrixXd& latent) {
  Reader in(record);
  seconds = in.next();
  log_likelihood = in.next();
  const auto rows = static_cast<Eigen::Index>(in.next()), cols = static_cast<Eigen::Index>(in.next());
  const auto values = in.next(static_cast<std::size_t>(rows * cols));
  latent = Eigen::Map<const Eigen::MatrixXd>(values.data(), rows, cols);
  in.end();
}

std::vector<double> projection_record(double seconds, const GramProjection& projection) {
  std::vector<double> out{seconds, projection.residual_squared};
  append(out, projection.x);
  append(out, projection.coefficients);
  out.push_back(static_cast<double>(projection.candidates.size()));
  for (const Eigen::VectorXd& candidate : projection.candidates) append(out, candidate);
  return out;
}

void read_projection_record(std::span<const double> record, double& seconds, GramProjection& projection) {
  Reader in(record);
  seconds = in.next();
  projection.residual_squared = in.next();
  projection.x = in.vector();
  projection.coefficients = in.vector();
  projection.candidates.resize(static_cast<std::size_t>(in.next()));
  for (Eigen::VectorXd& candidate : projection.candidates) candidate = in.vector();
  in.end();
}

}  // namespace matlas::eval
