// The acquisition endpoints of the API (docs/API.md): POST /api/fit-samples places a file of sparse
// measurements on the map, POST /api/sample-plan says which directions to measure. The files are
// parsed by formats/sample_file.h; every problem in them is a 400 with the parser's message.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "acquisition/model_samples.h"
#include "brdf/types.h"
#include "core/error.h"
#include "formats/sample_file.h"
#include "server/api.h"
#include "server/http_error.h"

namespace matlas::server {

namespace {

/// What a sample file is called in messages ("upload: line 7: theta_i = 95 is below the horizon").
constexpr const char* kUploadName = "upload";

nlohmann::json vector_json(const Eigen::VectorXd& v) {
  return nlohmann::json(std::vector<double>(v.data(), v.data() + v.size()));
}

nlohmann::json vec3_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

/// The samples of an uploaded file; invalid rows are skipped and listed, anything else wrong with
/// the file is a 400 naming the line.
SampleFile parse_upload(const std::string& text) {
  if (text.size() > kMaxSampleBody)
    throw HttpError(413, "the sample file has " + std::to_string(text.size()) + " bytes; at most " +
                             std::to_string(kMaxSampleBody) + " are accepted");
  SampleReadOptions options;
  options.skip_invalid = true;
  try {
    return parse_samples(text, kUploadName, options);
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // defensive: the parser reports its own errors as matlas::Error
    throw bad_request(std::string("upload: the sample file cannot be read: ") + e.what());
  }
}

/// Per fitted sample: its line, angles, measured and predicted RGB, residual, weights, whether it is
/// an outlier (model_rows adds a sample's three rows or none); `sum2` receives the residuals'
/// sum of squares.
nlohmann::json fitted_samples_json(const std::vector<MeasuredSample>& measured, const acquisition::SampleRows& rows,
                                   const acquisition::SparseFit& f, double* sum2_out) {
  nlohmann::json samples = nlohmann::json::array();
  double sum2 = 0;
  for (Eigen::Index r = 0; r + 2 < rows.rows(); r += 3) {
    const auto s = static_cast<std::size_t>(rows.sample[static_cast<std::size_t>(r)]);
    nlohmann::json value = nlohmann::json::array(), predicted = nlohmann::json::array(),
                   residual = nlohmann::json::array(), weight = nlohmann::json::array();
    for (Eigen::Index c = r; c < r + 3; ++c) {
      value.push_back(rows.measured[c]);
      predicted.push_back(f.predicted[c]);
      residual.push_back(f.residual[c]);
      weight.push_back(f.weight[c]);
      sum2 += f.residual[c] * f.residual[c];
    }
    const bool outlier = std::find(f.outliers.begin(), f.outliers.end(), static_cast<int>(s)) != f.outliers.end();
    const auto [theta_i, phi_i] = direction_angles(measured[s].wi);
    const auto [theta_o, phi_o] = direction_angles(measured[s].wo);
    samples.push_back({{"line", measured[s].line},
                       {"theta_i", theta_i}, {"phi_i", phi_i}, {"theta_o", theta_o}, {"phi_o", phi_o},
                       {"rgb", value}, {"predicted", predicted}, {"residual", residual}, {"weight", weight},
                       {"outlier", outlier}});
  }
  *sum2_out = sum2;
  return samples;
}

/// The latent covariance (q x q; NaN where it does not exist) and the 1-sigma per axis, with
/// null for what is not finite.
void covariance_json(const Eigen::MatrixXd& latent_covariance, int q, nlohmann::json* covariance_out,
                     nlohmann::json* sigma_out) {
  Eigen::MatrixXd cov = latent_covariance;
  if (cov.rows() != q || cov.cols() != q) cov = Eigen::MatrixXd::Constant(q, q, std::nan(""));
  nlohmann::json covariance = nlohmann::json::array(), sigma = nlohmann::json::array();
  for (int a = 0; a < q; ++a) {
    nlohmann::json row = nlohmann::json::array();
    for (int b = 0; b < q; ++b) row.push_back(std::isfinite(cov(a, b)) ? nlohmann::json(cov(a, b)) : nlohmann::json());
    covariance.push_back(row);
    const double v = cov(a, a);
    sigma.push_back(std::isfinite(v) && v >= 0 ? nlohmann::json(std::sqrt(v)) : nlohmann::json());
  }
  *covariance_out = std::move(covariance);
  *sigma_out = std::move(sigma);
}

}  // namespace

Reply Api::fit_samples(const std::string& file_text, const std::string& robust) {
  if (file_text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw bad_request("the upload is empty: send a sample file (CSV or JSON, docs/ACQUISITION.md) as the body");
  if (!robust.empty() && robust != "0" && robust != "1") throw bad_request("robust must be 0 or 1, got " + quoted_excerpt(robust));
  const SampleFile file = parse_upload(file_text);
  const std::vector<MeasuredSample> measured = file.measured();
  if (measured.empty()) {
    std::string why;
    if (!file.samples.empty())
      why = std::to_string(file.samples.size()) + " row" + (file.samples.size() == 1 ? " has" : "s have") +
            " no r, g, b (a plan not filled in?)";
    if (!file.skipped.empty())
      why += (why.empty() ? "" : "; ") + std::to_string(file.skipped.size()) + " invalid row" +
             (file.skipped.size() == 1 ? "" : "s") + " skipped, e.g. " + file.skipped.front();
    throw bad_request(std::string(kUploadName) + ": no measured samples to fit: " + why);
  }
  acquisition::SparseFitOptions options;
  options.transform = acquisition::model_transform(model_);
  options.robust = robust != "0";
  acquisition::ModelFit fit;
  {
    auto slot = acquire(heavy_);
    try {
      fit = acquisition::fit_samples(model_, measured, options);
    } catch (const HttpError&) {
      throw;
    } catch (const Error& e) {
      throw HttpError(422, std::string("the samples cannot be fitted: ") + e.what());
    }
  }
  const acquisition::SampleRows& rows = fit.rows;
  const acquisition::SparseFit& f = fit.fit;
  if (rows.rows() != f.residual.size()) throw HttpError(500, "the fit's rows do not match the samples");

  double sum2 = 0;
  const nlohmann::json samples = fitted_samples_json(measured, rows, f, &sum2);
  nlohmann::json covariance, sigma;
  covariance_json(f.latent_covariance, model_.dim(), &covariance, &sigma);
  // The weights that make the point, largest first (every one above 0.1 % of the largest, at most 16).
  const double largest = fit.weights.size() ? fit.weights.cwiseAbs().maxCoeff() : 0.0;
  int shown = 0;
  for (Eigen::Index i = 0; i < fit.weights.size(); ++i) shown += std::abs(fit.weights[i]) > 1e-3 * largest;
  nlohmann::json best = nullptr;
  if (f.best_input >= 0 && f.best_input < model_.count())
    best = {{"index", f.best_input}, {"name", model_.names()[static_cast<std::size_t>(f.best_input)]}};
  const auto rms = rows.rows() ? std::sqrt(sum2 / static_cast<double>(rows.rows())) : 0.0;
  return Reply::json({{"x", vector_json(f.x)},
                      {"variance", f.variance},
                      {"covariance", covariance},
                      {"latent_sigma", sigma},
                      {"weights", top_weights(fit.weights, std::min(shown, 16))},
                      {"best_input", best},
                      {"combined", f.combined},
                      {"samples", samples},
                      {"used", static_cast<int>(samples.size())},
                      {"outliers", static_cast<int>(f.outliers.size())},
                      {"rms_residual", rms},
                      {"scale", f.scale},
                      {"transform", options.transform.to_string()},
                      {"skipped", file.skipped},
                      {"unusable", fit.unusable}});
}

Reply Api::sample_plan(const std::string& file_text, const std::string& k_text) {
  const int k = k_text.empty() ? 20 : parse_int_text(k_text, "k", 1, 100);
  std::vector<MeasuredSample> measured;
  std::vector<std::string> skipped;
  if (file_text.find_first_not_of(" \t\r\n") != std::string::npos) {
    const SampleFile file = parse_upload(file_text);
    measured = file.measured();
    skipped = file.skipped;
  }
  acquisition::PlanOptions options;
  options.transform = acquisition::model_transform(model_);
  options.rank = std::max(1, std::min(options.rank, model_.count() - 1));
  acquisition::ModelPlan plan;
  {
    auto slot = acquire(heavy_);
    try {
      plan = acquisition::plan_samples(model_, k, measured, options);
    } catch (const HttpError&) {
      throw;
    } catch (const Error& e) {
      throw HttpError(422, std::string("no plan for this model: ") + e.what());
    }
  }
  nlohmann::json directions = nlohmann::json::array();
  for (std::size_t d = 0; d < plan.directions.size(); ++d) {
    const MeasuredSample& s = plan.directions[d];
    const auto [theta_i, phi_i] = direction_angles(s.wi);
    const auto [theta_o, phi_o] = direction_angles(s.wo);
    directions.push_back({{"theta_i", theta_i}, {"phi_i", phi_i}, {"theta_o", theta_o}, {"phi_o", phi_o},
                          {"wi", vec3_json(s.wi)}, {"wo", vec3_json(s.wo)},
                          {"gain", d < plan.plan.gain.size() ? plan.plan.gain[d] : 0.0}});
  }
  std::vector<std::string> comment = {"matlas sample plan: " + std::to_string(plan.directions.size()) +
                                      " directions for " + model_.path().filename().string()};
  if (plan.conditioned_on > 0)
    comment.push_back("given " + std::to_string(plan.conditioned_on) + " measured samples");
  return Reply::json({{"directions", directions},
                      {"remaining", plan.plan.remaining},
                      {"conditioned_on", plan.conditioned_on},
                      {"skipped", skipped},
                      {"csv", format_samples_csv(plan.directions, comment)}});
}

}  // namespace matlas::server
