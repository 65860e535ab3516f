#pragma once
// Parsing of latent points given on the command line (`--at x1,...,xq` or `--material NAME`).
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include "manifold/model.h"

namespace matlas::cli {

/// "0.1,-2,3e-1" -> vector; throws matlas::Error naming `flag` on an empty coordinate (a
/// trailing comma), a malformed, out-of-range or non-finite number.
Eigen::VectorXd parse_point(const std::string& text, const std::string& flag = "--at");

/// The coordinates as comma-separated shortest decimal texts that read back the same (JSON's, and
/// the server's downloads', server/export_api.cpp): how file descriptions name a point.
std::string point_text(const Eigen::VectorXd& x);

/// CLI11 check: the option's value is a finite number (not nan, inf, or out of double's range).
CLI::Validator finite_number();

/// The latent point named by exactly one of --at / --material, checked against the model's q.
Eigen::VectorXd resolve_point(const Model& model, const std::optional<std::string>& at,
                              const std::optional<std::string>& material);

/// Adds the --at and --material options to a command (exactly one of them is required).
void add_point_options(CLI::App& cmd, std::optional<std::string>& at,
                       std::optional<std::string>& material);

}  // namespace matlas::cli
