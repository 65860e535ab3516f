#include "formats/sample_file.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"

namespace matlas {

std::vector<MeasuredSample> SampleFile::measured() const {
  std::vector<MeasuredSample> out;
  for (const auto& s : samples)
    if (s.measured) out.push_back(s);
  return out;
}

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
constexpr std::size_t kListedProblems = 10;

/// A sample as written in the file, before its checks: directions as given, values in the row's
/// quantity.
struct RawRow {
  bool angles = true;  // theta/phi (degrees) or vectors
  std::array<double, 4> theta_phi{};  // theta_i, phi_i, theta_o, phi_o
  Vec3 wi = Vec3::Zero(), wo = Vec3::Zero();
  bool has_value = false;
  std::array<double, 3> value{};
  std::array<double, 3> sigma{};
  bool ratio = false;
  int line = 0;
};

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

Vec3 direction_of(double theta_deg, double phi_deg) {
  const double t = theta_deg * kDegree, p = phi_deg * kDegree;
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

/// Checks a row and converts it; returns the problem ("theta_i = 95 is below the horizon") or
/// nothing.
std::optional<std::string> convert(const RawRow& row, MeasuredSample& out) {
  out.line = row.line;
  out.measured = row.has_value;
  if (row.angles) {
    static const char* names[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(row.theta_phi[static_cast<std::size_t>(k)]))
        return std::string(names[k]) + " is not finite";
    for (int k : {0, 2}) {
      const double t = row.theta_phi[static_cast<std::size_t>(k)];
      if (t >= 90) return std::string(names[k]) + " = " + number_text(t) + " is at or below the horizon";
      if (t < 0) return std::string(names[k]) + " = " + number_text(t) + " is negative (expected 0 <= theta < 90)";
    }
    out.wi = direction_of(row.theta_phi[0], row.theta_phi[1]);
    out.wo = direction_of(row.theta_phi[2], row.theta_phi[3]);
  } else {
    for (const auto& [v, name] : {std::pair{row.wi, "wi"}, std::pair{row.wo, "wo"}}) {
      if (!v.allFinite()) return std::string(name) + " is not finite";
      if (v.norm() == 0) return std::string(name) + " is the zero vector";
      if (v.z() / v.norm() <= 1e-9) return std::string(name) + " is at or below the horizon (z = " + number_text(v.z()) + ")";
    }
    out.wi = row.wi.normalized();
    out.wo = row.wo.normalized();
  }
  if (!row.has_value) return std::nullopt;
  static const char* channels[3] = {"r", "g", "b"};
  const double scale = row.ratio ? 1.0 / out.wi.z() : 1.0;  // ratio = f cos(theta_i)
  for (std::size_t c = 0; c < 3; ++c) {
    const double v = row.value[c], s = row.sigma[c];
    if (!std::isfinite(v)) return std::string(channels[c]) + " is not finite";
    if (v < 0) return std::string(channels[c]) + " = " + number_text(v) + " is negative";
    if (!std::isfinite(s)) return std::string("sigma_") + channels[c] + " is not finite";
    if (s < 0) return std::string("sigma_") + channels[c] + " = " + number_text(s) + " is negative";
    out.value[static_cast<Eigen::Index>(c)] = v * scale;
    out.sigma[static_cast<Eigen::Index>(c)] = s * scale;
  }
  return std::nullopt;
}

SampleFile finish(const std::vector<RawRow>& rows, const std::string& name, bool json,
                  const SampleReadOptions& options) {
  SampleFile file;
  file.json = json;
  const std::string where = json ? "sample " : "line ";
  std::vector<std::string> problems;
  for (const auto& row : rows) {
    MeasuredSample s;
    if (auto problem = convert(row, s)) problems.push_back(where + std::to_string(row.line) + ": " + *problem);
    else file.samples.push_back(s);
  }
  if (!problems.empty() && !options.skip_invalid) {
    std::string message = std::to_string(problems.size()) + " invalid sample" + (problems.size() == 1 ? "" : "s") +
                          " (to skip them: --skip-invalid, or skip_invalid=True in Python):";
    for (std::size_t k = 0; k < std::min(problems.size(), kListedProblems); ++k) message += "\n  " + problems[k];
    if (problems.size() > kListedProblems)
      message += "\n  ... and " + std::to_string(problems.size() - kListedProblems) + " more";
    throw file_error(name, message);
  }
  file.skipped = std::move(problems);
  if (file.samples.empty() && file.skipped.empty()) throw file_error(name, "no samples");
  return file;
}

// --- CSV ---

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') s = s.substr(1, s.size() - 2);
  return s;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

/// A quoted excerpt of a cell for messages (at most 40 characters).
std::string excerpt(std::string_view s) {
  std::string out = "'";
  for (char c : s.substr(0, 40)) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return out + (s.size() > 40 ? "...'" : "'");
}

SampleFile parse_csv(const std::string& text, const std::string& name, const SampleReadOptions& options) {
  std::map<std::string, std::size_t> column;
  std::vector<RawRow> rows;
  int line_number = 0;
  bool header = false;
  std::size_t pos = 0;
  auto fail = [&](const std::string& what) { return file_error(name, "line " + std::to_string(line_number) + ": " + what); };
  auto has = [&](const char* c) { return column.count(c) != 0; };
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line(text.data() + pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') {
      if (end == text.size()) break;
      continue;
    }
    const auto cells = split(line);
    if (!header) {
      for (std::size_t k = 0; k < cells.size(); ++k) {
        const std::string key = lower(cells[k]);
        if (!key.empty() && !column.emplace(key, k).second) throw fail("column '" + key + "' appears twice");
      }
      const bool angles = has("theta_i") && has("phi_i") && has("theta_o") && has("phi_o");
      const bool vectors = has("wi_x") && has("wi_y") && has("wi_z") && has("wo_x") && has("wo_y") && has("wo_z");
      if (!angles && !vectors)
        throw fail("the header names no directions (expected columns theta_i,phi_i,theta_o,phi_o in degrees, or "
                   "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z)");
      if (!(has("r") && has("g") && has("b"))) throw fail("the header has no r,g,b columns");
      header = true;
      if (end == text.size()) break;
      continue;
    }
    auto cell = [&](const char* key) -> std::string_view {
      const auto it = column.find(key);
      if (it == column.end() || it->second >= cells.size()) return {};
      return cells[it->second];
    };
    auto number = [&](const char* key, bool required) -> std::optional<double> {
      const std::string_view c = cell(key);
      if (c.empty()) {
        if (required) throw fail("column '" + std::string(key) + "' is empty");
        return std::nullopt;
      }
      double v = 0;
      const char* first = c.data();
      if (*first == '+') ++first;
      const auto [ptr, ec] = std::from_chars(first, c.data() + c.size(), v);
      if (ec != std::errc() || ptr != c.data() + c.size())
        throw fail("column '" + std::string(key) + "': " + excerpt(c) + " is not a number");
      return v;
    };
    RawRow row;
    row.line = line_number;
    row.angles = has("theta_i") && has("phi_i") && has("theta_o") && has("phi_o");
    if (row.angles) {
      row.theta_phi = {*number("theta_i", true), *number("phi_i", true), *number("theta_o", true), *number("phi_o", true)};
    } else {
      row.wi = {*number("wi_x", true), *number("wi_y", true), *number("wi_z", true)};
      row.wo = {*number("wo_x", true), *number("wo_y", true), *number("wo_z", true)};
    }
    const std::optional<double> r = number("r", false), g = number("g", false), b = number("b", false);
    const int present = int(r.has_value()) + int(g.has_value()) + int(b.has_value());
    if (present != 0 && present != 3) throw fail("r, g and b must all be given or all be empty");
    row.has_value = present == 3;
    if (row.has_value) row.value = {*r, *g, *b};
    if (const auto s = number("sigma", false)) row.sigma = {*s, *s, *s};
    static const char* sigma_names[3] = {"sigma_r", "sigma_g", "sigma_b"};
    for (std::size_t c = 0; c < 3; ++c)
      if (const auto s = number(sigma_names[c], false)) row.sigma[c] = *s;
    const std::string quantity = lower(cell("quantity"));
    if (quantity == "ratio") row.ratio = true;
    else if (!quantity.empty() && quantity != "brdf")
      throw fail("quantity " + excerpt(quantity) + " is neither 'brdf' nor 'ratio'");
    rows.push_back(row);
    if (end == text.size()) break;
  }
  if (!header) throw file_error(name, "no header row (expected e.g. theta_i,phi_i,theta_o,phi_o,r,g,b)");
  return finish(rows, name, false, options);
}

// --- JSON ---

SampleFile parse_json(const std::string& text, const std::string& name, const SampleReadOptions& options) {
  using nlohmann::json;
  json doc;
  // Sample files are shallow ({"samples": [{"wi": [...]}]}): deeper nesting is refused while
  // parsing, before a deep document is built (destroying one recurses per level).
  constexpr int kMaxDepth = 8;
  const json::parser_callback_t depth_guard = [&](int depth, json::parse_event_t, json&) {
    if (depth > kMaxDepth) throw file_error(name, "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels");
    return true;
  };
  try {
    doc = json::parse(text, depth_guard);
  } catch (const json::exception& e) {
    throw file_error(name, std::string("not valid JSON: ") + e.what());
  }
  const json* list = &doc;
  if (doc.is_object()) {
    if (!doc.contains("samples")) throw file_error(name, "a JSON sample file needs a \"samples\" array");
    list = &doc["samples"];
  }
  if (!list->is_array()) throw file_error(name, "\"samples\" is not an array");
  std::vector<RawRow> rows;
  int k = 0;
  for (const json& s : *list) {
    ++k;
    auto fail = [&](const std::string& what) { return file_error(name, "sample " + std::to_string(k) + ": " + what); };
    if (!s.is_object()) throw fail("not an object");
    auto number = [&](const json& v, const std::string& what) {
      if (!v.is_number()) throw fail(what + " is not a number");
      return v.get<double>();
    };
    auto vector3 = [&](const char* key) {
      const json& v = s[key];
      if (!v.is_array() || v.size() != 3) throw fail(std::string(key) + " is not an array of 3 numbers");
      return std::array<double, 3>{number(v[0], key), number(v[1], key), number(v[2], key)};
    };
    RawRow row;
    row.line = k;
    if (s.contains("wi") || s.contains("wo")) {
      if (!s.contains("wi") || !s.contains("wo")) throw fail("needs both wi and wo");
      row.angles = false;
      const auto wi = vector3("wi"), wo = vector3("wo");
      row.wi = {wi[0], wi[1], wi[2]};
      row.wo = {wo[0], wo[1], wo[2]};
    } else {
      static const char* keys[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};
      for (std::size_t c = 0; c < 4; ++c) {
        if (!s.contains(keys[c])) throw fail(std::string("needs ") + keys[c] + " (or wi and wo)");
        row.theta_phi[c] = number(s[keys[c]], keys[c]);
      }
    }
    if (s.contains("rgb") && !s["rgb"].is_null()) {
      row.value = vector3("rgb");
      row.has_value = true;
    }
    if (s.contains("sigma") && !s["sigma"].is_null()) {
      if (s["sigma"].is_array()) row.sigma = vector3("sigma");
      else row.sigma.fill(number(s["sigma"], "sigma"));
    }
    if (s.contains("quantity")) {
      const json& q = s["quantity"];
      if (!q.is_string() || (q != "brdf" && q != "ratio")) throw fail("quantity is neither \"brdf\" nor \"ratio\"");
      row.ratio = q == "ratio";
    }
    rows.push_back(row);
  }
  return finish(rows, name, true, options);
}

}  // namespace

SampleFile parse_samples(const std::string& text, const std::string& name, const SampleReadOptions& options) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && (text[first] == '{' || text[first] == '[')) return parse_json(text, name, options);
  return parse_csv(text, name, options);
}

SampleFile read_samples(const std::filesystem::path& path, const SampleReadOptions& options) {
  return parse_samples(read_file(path), path.string(), options);
}

DirectionAngles direction_angles(const Vec3& w) {
  double phi = std::atan2(w.y(), w.x()) / kDegree;
  if (phi < 0) phi += 360;
  if (phi >= 360) phi = 0;
  return {std::acos(std::clamp(w.z(), -1.0, 1.0)) / kDegree, phi};
}

std::string format_samples_csv(const std::vector<MeasuredSample>& samples, const std::vector<std::string>& comment) {
  std::string out;
  for (const auto& c : comment) out += "# " + c + "\n";
  out += "theta_i,phi_i,theta_o,phi_o,quantity,r,g,b,sigma_r,sigma_g,sigma_b\n";
  char buf[256];
  for (const auto& s : samples) {
    const DirectionAngles i = direction_angles(s.wi), o = direction_angles(s.wo);
    std::snprintf(buf, sizeof buf, "%.6f,%.6f,%.6f,%.6f,brdf", i.theta, i.phi, o.theta, o.phi);
    out += buf;
    if (s.measured) {
      std::snprintf(buf, sizeof buf, ",%.9g,%.9g,%.9g", s.value[0], s.value[1], s.value[2]);
      out += buf;
      if ((s.sigma > 0).any()) std::snprintf(buf, sizeof buf, ",%.9g,%.9g,%.9g", s.sigma[0], s.sigma[1], s.sigma[2]);
      else std::snprintf(buf, sizeof buf, ",,,");
      out += buf;
    } else {
      out += ",,,,,,";
    }
    out += "\n";
  }
  return out;
}

}  // namespace matlas
