#include "cli/latent_point.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace matlas::cli {

std::string point_text(const Eigen::VectorXd& x) {
  std::string s;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (i > 0) s += ',';
    s += nlohmann::json(x[i]).dump();
  }
  return s;
}

Eigen::VectorXd parse_point(const std::string& text, const std::string& flag) {
  const auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  std::vector<double> values;
  std::size_t start = 0;
  for (;;) {
    // Every comma separates two coordinates: "0.05, " and "0,0," have an empty last one.
    const std::size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    while (!item.empty() && is_space(item.back())) item.pop_back();
    std::size_t lead = 0;
    while (lead < item.size() && is_space(item[lead])) ++lead;
    item.erase(0, lead);
    const std::string position = std::to_string(values.size() + 1);
    if (item.empty())
      throw Error(flag + " '" + text + "': coordinate " + position + " is empty (expected x1,...,xq)");
    const char* begin = item.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(begin, &end);
    if (end != begin + item.size())
      throw Error(flag + " '" + text + "': coordinate " + position + " '" + item + "' is not a number");
    if (!std::isfinite(v) || errno == ERANGE)
      throw Error(flag + " '" + text + "': coordinate " + position + " '" + item + "' is not a finite number");
    values.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(begin, &end);
        if (end == begin || *end != '\0') return "'" + text + "' is not a number";
        if (!std::isfinite(v) || errno == ERANGE) return "'" + text + "' is not a finite number";
        return {};
      },
      "FINITE");
}

Eigen::VectorXd resolve_point(const Model& model, const std::optional<std::string>& at,
                              const std::optional<std::string>& material) {
  if (material) return model.latent().row(model.index_of(*material)).transpose();
  if (!at) throw Error("give a latent point with --at x1,...,xq or --material NAME");
  Eigen::VectorXd x = parse_point(*at, "--at");
  if (x.size() != model.dim())
    throw Error("--at has " + std::to_string(x.size()) + " coordinates but the model has q = " +
                std::to_string(model.dim()));
  return x;
}

void add_point_options(CLI::App& cmd, std::optional<std::string>& at,
                       std::optional<std::string>& material) {
  auto* a = cmd.add_option("--at", at, "Latent point x1,...,xq");
  auto* m = cmd.add_option("--material", material, "A database material's own latent point");
  a->excludes(m);
}

}  // namespace matlas::cli
