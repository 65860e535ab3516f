#pragma once
// Parsing and validation of JSON request bodies. Every function throws HttpError(400) with a
// message naming the field and the problem (malformed JSON, wrong type, wrong dimension, NaN,
// out of range), so that a handler never sees an invalid value.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace matlas::server {

/// The latent coordinates a request may ask for: a box around the data's bounding box, enlarged
/// by `margin` times its extent on every side (far from the data the GP returns the mean).
struct LatentDomain {
  Eigen::VectorXd lo, hi;

  /// The box [min - margin * extent, max + margin * extent] per dimension; a dimension of zero
  /// extent gets a half-width of 1.
  static LatentDomain around(const Eigen::VectorXd& data_min, const Eigen::VectorXd& data_max,
                             double margin = 1.0);
  int dim() const { return static_cast<int>(lo.size()); }
};

/// Largest JSON request body (413 above): a request is a few numbers; 64 KiB leaves room.
inline constexpr std::size_t kMaxJsonBody = 64u << 10;
/// Largest sample file (POST /api/fit-samples, /api/sample-plan; 413 above): a few thousand
/// measurements as CSV or JSON.
inline constexpr std::size_t kMaxSampleBody = 1u << 20;
/// Deepest nesting of arrays and objects accepted in a JSON request (400 deeper).
inline constexpr std::size_t kMaxJsonDepth = 16;

/// Parses a request body that must be a JSON object of at most kMaxJsonBody bytes and
/// kMaxJsonDepth levels of nesting (checked before parsing).
nlohmann::json parse_json_object(const std::string& body);

/// The deepest nesting of arrays and objects in JSON text (brackets inside strings ignored);
/// stops counting once past `limit`.
std::size_t json_nesting_depth(const std::string& text, std::size_t limit);

/// A JSON value that must be an integer in [lo, hi]; `what` names it in errors. Integers of any
/// size are compared exactly (no 32-bit wrap-around), and the value is never printed whole.

/// The latent point `body[key]`: an array of exactly domain.dim() finite numbers inside the domain.
Eigen::VectorXd parse_latent(const nlohmann::json& body, const std::string& key,
                             const LatentDomain& domain);

/// Optional number `body[key]` in [lo, hi] (default when absent or null).
double parse_number(const nlohmann::json& body, const std::string& key, double lo, double hi,
                    double fallback);

int parse_int_value(const nlohmann::json& value, const std::string& what, int lo, int hi);

/// Optional integer `body[key]` in [lo, hi] (default when absent or null).
int parse_int(const nlohmann::json& body, const std::string& key, int lo, int hi, int fallback);

/// Optional boolean `body[key]` (default when absent or null); anything but true/false is refused.
bool parse_flag(const nlohmann::json& body, const std::string& key, bool fallback);

/// Optional string `body[key]` that must be one of `allowed` (default when absent or null).
std::string parse_choice(const nlohmann::json& body, const std::string& key,
                         const std::vector<std::string>& allowed, const std::string& fallback);

/// Integer text (a query parameter or a path segment) in [lo, hi]; `what` names it in errors.
int parse_int_text(const std::string& text, const std::string& what, int lo, int hi);

/// A latent point given as text (a query parameter): domain.dim() comma-separated numbers inside
/// the domain; `what` names it in errors.
Eigen::VectorXd parse_latent_text(const std::string& text, const std::string& what, const LatentDomain& domain);

/// A number given as text in [lo, hi]; `what` names it in errors.
double parse_number_text(const std::string& text, const std::string& what, double lo, double hi);

/// An Accept-Encoding header's value without the content coding `coding` (case-insensitive; its
/// parameters, such as q=, go with it): "gzip, deflate, br" without "br" is "gzip, deflate".
std::string accept_encoding_without(const std::string& value, const std::string& coding);

}  // namespace matlas::server
