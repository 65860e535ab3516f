#include "server/request_parsing.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cctype>
#include <cmath>
#include <sstream>

#include "server/http_error.h"

namespace matlas::server {

namespace {

std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

const nlohmann::json* field(const nlohmann::json& body, const std::string& key) {
  const auto it = body.find(key);
  if (it == body.end() || it->is_null()) return nullptr;
  return &*it;
}

double finite_number(const nlohmann::json& value, const std::string& what) {
  if (!value.is_number()) throw bad_request(what + " must be a number, got " + std::string(value.type_name()));
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw bad_request(what + " must be finite");
  return v;
}

}  // namespace

std::string quoted_excerpt(std::string_view value, std::size_t max_bytes) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "\"";
  const std::size_t shown = std::min(value.size(), max_bytes);
  for (std::size_t i = 0; i < shown; ++i) {
    const auto c = static_cast<unsigned char>(value[i]);
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  out += shown < value.size() ? "...\" (" + std::to_string(value.size()) + " bytes)" : "\"";
  return out;
}

LatentDomain LatentDomain::around(const Eigen::VectorXd& data_min, const Eigen::VectorXd& data_max,
                                  double margin) {
  LatentDomain d;
  d.lo.resize(data_min.size());
  d.hi.resize(data_min.size());
  for (Eigen::Index i = 0; i < data_min.size(); ++i) {
    const double extent = data_max[i] - data_min[i];
    const double pad = extent > 0 ? margin * extent : 1.0;
    d.lo[i] = data_min[i] - pad;
    d.hi[i] = data_max[i] + pad;
  }
  return d;
}

std::size_t json_nesting_depth(const std::string& text, std::size_t limit) {
  // Brackets outside strings; a string ends at an unescaped quote. Stops early past the limit.
  std::size_t depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest && (deepest = depth) > limit) return deepest;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

nlohmann::json parse_json_object(const std::string& body) {
  if (body.size() > kMaxJsonBody)
    throw HttpError(413, "the request body has " + std::to_string(body.size()) + " bytes; JSON requests are limited to " +
                             std::to_string(kMaxJsonBody));
  // Requests are shallow ({"x": [...], "rect": [...]}): deeper nesting is refused before parsing,
  // so that nothing recursive (printing, comparing, copying) ever meets a deep value.
  if (json_nesting_depth(body, kMaxJsonDepth) > kMaxJsonDepth)
    throw bad_request("the request body nests arrays or objects deeper than " + std::to_string(kMaxJsonDepth) +
                      " levels");
  // nlohmann's lexer reads a NUL byte as the end of the input: "{}\0garbage" would parse as {}.
  if (body.find('\0') != std::string::npos)
    throw bad_request("the request body contains a NUL byte (at offset " + std::to_string(body.find('\0')) +
                      "); send JSON text");
  // nlohmann's parser rejects NaN/Infinity literals, so every number that gets through is finite
  // unless it overflows (1e999 parses as inf), which finite_number() catches.
  nlohmann::json j = nlohmann::json::parse(body, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw bad_request("the request body is not valid JSON");
  if (!j.is_object()) throw bad_request("the request body must be a JSON object");
  return j;
}

int parse_int_value(const nlohmann::json& value, const std::string& what, int lo, int hi) {
  if (!value.is_number_integer())
    throw bad_request(what + " must be an integer, got " + std::string(value.is_number() ? "a fractional number"
                                                                                         : value.type_name()));
  // Compared as 64-bit (signed or unsigned as stored): 2^32 or 2^64 - 1 must not wrap into range.
  const bool too_big = value.is_number_unsigned() ? value.get<std::uint64_t>() > static_cast<std::uint64_t>(hi)
                                                  : value.get<std::int64_t>() > hi;
  // nlohmann stores every non-negative integer as unsigned: the lower bound applies to those too.
  const bool too_small = value.is_number_unsigned()
                             ? lo > 0 && value.get<std::uint64_t>() < static_cast<std::uint64_t>(lo)
                             : value.get<std::int64_t>() < lo;
  if (too_big || too_small)
    throw bad_request(what + " = " +
                      (value.is_number_unsigned() ? std::to_string(value.get<std::uint64_t>())
                                                  : std::to_string(value.get<std::int64_t>())) +
                      " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(value.get<std::int64_t>());
}

Eigen::VectorXd parse_latent(const nlohmann::json& body, const std::string& key,
                             const LatentDomain& domain) {
  const nlohmann::json* value = field(body, key);
  if (!value) throw bad_request("missing field \"" + key + "\" (the latent point, an array of " +
                                std::to_string(domain.dim()) + " numbers)");
  if (!value->is_array())
    throw bad_request("\"" + key + "\" must be an array of numbers, got " + std::string(value->type_name()));
  if (static_cast<int>(value->size()) != domain.dim())
    throw bad_request("\"" + key + "\" has " + std::to_string(value->size()) +
                      " coordinates but the model's latent space has " + std::to_string(domain.dim()));
  Eigen::VectorXd x(domain.dim());
  for (int i = 0; i < domain.dim(); ++i) {
    const std::string what = key + "[" + std::to_string(i) + "]";
    x[i] = finite_number((*value)[static_cast<std::size_t>(i)], what);
    if (x[i] < domain.lo[i] || x[i] > domain.hi[i])
      throw bad_request(what + " = " + number_text(x[i]) + " is outside the allowed range [" +
                        number_text(domain.lo[i]) + ", " + number_text(domain.hi[i]) + "]");
  }
  return x;
}

double parse_number(const nlohmann::json& body, const std::string& key, double lo, double hi,
                    double fallback) {
  const nlohmann::json* value = field(body, key);
  if (!value) return fallback;
  const double v = finite_number(*value, "\"" + key + "\"");
  if (v < lo || v > hi)
    throw bad_request("\"" + key + "\" = " + number_text(v) + " is outside [" + number_text(lo) + ", " +
                      number_text(hi) + "]");
  return v;
}

int parse_int(const nlohmann::json& body, const std::string& key, int lo, int hi, int fallback) {
  const nlohmann::json* value = field(body, key);
  if (!value) return fallback;
  return parse_int_value(*value, "\"" + key + "\"", lo, hi);
}

bool parse_flag(const nlohmann::json& body, const std::string& key, bool fallback) {
  const nlohmann::json* value = field(body, key);
  if (!value) return fallback;
  if (!value->is_boolean()) throw bad_request("\"" + key + "\" must be true or false, got " + std::string(value->type_name()));
  return value->get<bool>();
}

std::string parse_choice(const nlohmann::json& body, const std::string& key,
                         const std::vector<std::string>& allowed, const std::string& fallback) {
  const nlohmann::json* value = field(body, key);
  if (!value) return fallback;
  if (!value->is_string()) throw bad_request("\"" + key + "\" must be a string");
  const std::string s = value->get<std::string>();
  for (const auto& a : allowed)
    if (a == s) return s;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  throw bad_request("unknown " + key + " " + quoted_excerpt(s) + " (choose one of: " + list + ")");
}

int parse_int_text(const std::string& text, const std::string& what, int lo, int hi) {
  int v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size())
    throw bad_request(what + " must be an integer, got " + quoted_excerpt(text));
  if (v < lo || v > hi)
    throw bad_request(what + " = " + std::to_string(v) + " is outside [" + std::to_string(lo) + ", " +
                      std::to_string(hi) + "]");
  return v;
}

namespace {

double number_from_text(const std::string& text, const std::string& what) {
  double v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
    throw bad_request(what + " must be a finite number, got " + quoted_excerpt(text));
  return v;
}

}  // namespace

Eigen::VectorXd parse_latent_text(const std::string& text, const std::string& what, const LatentDomain& domain) {
  if (text.empty())
    throw bad_request("missing parameter " + what + " (the latent point, " + std::to_string(domain.dim()) +
                      " comma-separated numbers)");
  nlohmann::json values = nlohmann::json::array();
  std::size_t begin = 0;
  for (;;) {
    const std::size_t comma = text.find(',', begin);
    values.push_back(number_from_text(text.substr(begin, comma - begin),
                                      what + "[" + std::to_string(values.size()) + "]"));
    if (comma == std::string::npos || values.size() > 64) break;
    begin = comma + 1;
  }
  return parse_latent(nlohmann::json{{what, values}}, what, domain);
}

double parse_number_text(const std::string& text, const std::string& what, double lo, double hi) {
  return parse_number(nlohmann::json{{what, number_from_text(text, what)}}, what, lo, hi, 0.0);
}

std::string accept_encoding_without(const std::string& value, const std::string& coding) {
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string unwanted = lower(coding);
  std::string kept;
  for (std::size_t from = 0; from <= value.size();) {
    const std::size_t comma = std::min(value.find(',', from), value.size());
    std::string item = value.substr(from, comma - from);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    const std::string name = item.substr(0, item.find_first_of(" \t;"));
    if (!name.empty() && lower(name) != unwanted) kept += (kept.empty() ? "" : ", ") + item;
    from = comma + 1;
  }
  return kept;
}

}  // namespace matlas::server
