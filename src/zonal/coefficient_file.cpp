#include "formats/half_float.h"
#include "zonal/coefficient_file.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "zonal/basis.h"
#include "zonal/sh.h"

namespace matlas::zonal {

namespace {

/// One material's values in the storage type, appended to bytes; updates the largest error.
void encode(const std::vector<double>& values, DType storage, std::vector<std::byte>& bytes, double* max_error) {
  for (double v : values) {
    const float f = static_cast<float>(v);
    if (storage == DType::F16) {
      const std::uint16_t h = float_to_half(f);
      *max_error = std::max(*max_error, std::abs(static_cast<double>(half_to_float(h)) - v));
      const auto* p = reinterpret_cast<const std::byte*>(&h);
      bytes.insert(bytes.end(), p, p + 2);
    } else {
      *max_error = std::max(*max_error, std::abs(static_cast<double>(f) - v));
      const auto* p = reinterpret_cast<const std::byte*>(&f);
      bytes.insert(bytes.end(), p, p + 4);
    }
  }
}

std::vector<double> decode(const SafetensorsFile& file, const TensorInfo& t, std::size_t first, std::size_t count) {
  std::vector<double> out(count);
  const std::byte* data = file.bytes(t);
  for (std::size_t i = 0; i < count; ++i) {
    if (t.dtype == DType::F16) {
      std::uint16_t h;
      std::memcpy(&h, data + 2 * (first + i), 2);
      out[i] = half_to_float(h);
    } else {
      float f;
      std::memcpy(&f, data + 4 * (first + i), 4);
      out[i] = f;
    }
  }
  return out;
}

int metadata_int(const SafetensorsFile& file, const std::string& key) {
  const auto it = file.metadata().find(key);
  if (it == file.metadata().end()) throw Error(file.path().string() + ": metadata '" + key + "' is missing");
  try {
    return std::stoi(it->second);
  } catch (const std::exception&) {
    throw Error(file.path().string() + ": metadata '" + key + "' is not an integer");
  }
}

}  // namespace

double write_coefficients(const std::filesystem::path& path, const CoefficientSet& set, DType storage) {
  if (storage != DType::F32 && storage != DType::F16) throw Error("coefficient storage must be f32 or f16");
  if (set.materials.empty() || set.materials.size() != set.names.size())
    throw Error("coefficient set of " + std::to_string(set.materials.size()) + " materials and " +
                std::to_string(set.names.size()) + " names");
  const ProjectionSettings& s = set.settings;
  const ZonalBasis basis(s.bands);
  const auto T = static_cast<std::int64_t>(s.theta_o_count), K = static_cast<std::int64_t>(basis.size());
  const auto S = K + static_cast<std::int64_t>(s.lobes.size());
  const std::size_t per = static_cast<std::size_t>(T * S * 3);
  double scale = 0, error = 0;
  std::vector<std::byte> coeffs, mean;
  for (const ZonalCoefficients& c : set.materials) {
    if (c.bands != s.bands || c.theta_o_count != s.theta_o_count || c.lobes != s.lobes || c.values.size() != per)
      throw Error("coefficient set: a material's layout differs from the settings");
    for (double v : c.values) scale = std::max(scale, std::abs(v));
    encode(c.values, storage, coeffs, &error);
  }
  if (set.mean) encode(set.mean->values, storage, mean, &error);
  const double relative = scale > 0 ? error / scale : 0.0;

  SafetensorsWriter w;
  w.add_metadata("format", "matlas-zonal");
  w.add_metadata("version", "2");
  w.add_metadata("bands", std::to_string(s.bands));
  w.add_metadata("theta_o_count", std::to_string(s.theta_o_count));
  w.add_metadata("theta_rows", std::to_string(s.theta_rows));
  w.add_metadata("phi_columns", std::to_string(s.phi_columns));
  w.add_metadata("lobes", nlohmann::json(s.lobes).dump());
  if (s.ring_floor >= 0.0) w.add_metadata("ring_floor", nlohmann::json(s.ring_floor).dump());
  w.add_metadata("names", nlohmann::json(set.names).dump());
  w.add_metadata("storage", storage == DType::F16 ? "f16" : "f32");
  w.add_metadata("storage_error", std::to_string(relative));
  if (!set.source_key.empty()) w.add_metadata("source_key", set.source_key);
  w.declare("coefficients", storage, {static_cast<std::int64_t>(set.materials.size()), T, S, 3});
  if (set.mean) w.declare("mean", storage, {T, S, 3});
  w.declare("alpha", DType::F32, {K});
  w.declare("band", DType::I32, {K});
  w.declare("theta_o", DType::F32, {T});
  w.begin(path);
  w.write(coeffs.data(), coeffs.size());
  if (set.mean) w.write(mean.data(), mean.size());
  std::vector<float> alpha;
  std::vector<std::int32_t> band;
  std::vector<float> theta;
  for (std::size_t j = 0; j < basis.size(); ++j) {
    alpha.push_back(static_cast<float>(basis.alpha(j)));
    band.push_back(basis.band(j));
  }
  for (int t = 0; t < s.theta_o_count; ++t) theta.push_back(static_cast<float>(ZonalCoefficients::theta_o(t, s.theta_o_count)));
  w.write(std::span<const float>(alpha));
  w.write(std::span<const std::int32_t>(band));
  w.write(std::span<const float>(theta));
  w.commit();
  return relative;
}

CoefficientSet read_coefficients(const std::filesystem::path& path) {
  const SafetensorsFile file = SafetensorsFile::open(path);
  const auto format = file.metadata().find("format");
  if (format == file.metadata().end() || format->second != "matlas-zonal")
    throw Error(path.string() + ": not a matlas zonal coefficient file (metadata format is not matlas-zonal)");
  const auto version = file.metadata().find("version");
  const std::string v = version == file.metadata().end() ? "1" : version->second;
  if (v != "1" && v != "2")
    throw Error(path.string() + ": zonal coefficient file version " + v +
                " is newer than this matlas reads (1 and 2); recompute it with `matlas zonal` or update matlas");
  CoefficientSet set;
  if (const auto key = file.metadata().find("source_key"); key != file.metadata().end()) set.source_key = key->second;
  set.settings.bands = metadata_int(file, "bands");
  set.settings.theta_o_count = metadata_int(file, "theta_o_count");
  set.settings.theta_rows = metadata_int(file, "theta_rows");
  set.settings.phi_columns = metadata_int(file, "phi_columns");
  try {
    set.settings.validate();
    set.names = nlohmann::json::parse(file.metadata().at("names")).get<std::vector<std::string>>();
  } catch (const Error& e) {
    throw Error(path.string() + ": " + e.what());
  } catch (const std::exception&) {
    throw Error(path.string() + ": metadata 'names' is not a JSON array of strings");
  }
  if (v == "2") {
    try {
      set.settings.lobes = nlohmann::json::parse(file.metadata().at("lobes")).get<std::vector<double>>();
      validate_lobes(set.settings.lobes);
    } catch (const Error& e) {
      throw Error(path.string() + ": " + e.what());
    } catch (const std::exception&) {
      throw Error(path.string() + ": metadata 'lobes' is missing or not a JSON array of numbers");
    }
    if (const auto it = file.metadata().find("ring_floor"); it != file.metadata().end()) {
      try {
        set.settings.ring_floor = nlohmann::json::parse(it->second).get<double>();
        set.settings.validate();
      } catch (const Error& e) {
        throw Error(path.string() + ": " + e.what());
      } catch (const std::exception&) {
        throw Error(path.string() + ": metadata 'ring_floor' is not a number");
      }
    }
  }
  const std::int64_t T = set.settings.theta_o_count,
                     K = static_cast<std::int64_t>(triangle_size(set.settings.bands) + set.settings.lobes.size());
  const TensorInfo* c = file.find("coefficients");
  if (!c || (c->dtype != DType::F32 && c->dtype != DType::F16))
    throw Error(path.string() + ": tensor 'coefficients' is missing or not F32/F16");
  const auto n = static_cast<std::int64_t>(set.names.size());
  file.require("coefficients", c->dtype, {n, T, K, 3});
  const std::size_t per = static_cast<std::size_t>(T * K * 3);
  for (std::int64_t i = 0; i < n; ++i) {
    ZonalCoefficients z;
    z.bands = set.settings.bands;
    z.theta_o_count = set.settings.theta_o_count;
    z.lobes = set.settings.lobes;
    z.values = decode(file, *c, static_cast<std::size_t>(i) * per, per);
    set.materials.push_back(std::move(z));
  }
  if (file.find("mean")) {
    const TensorInfo& m = file.require("mean", c->dtype, {T, K, 3});
    ZonalCoefficients z;
    z.bands = set.settings.bands;
    z.theta_o_count = set.settings.theta_o_count;
    z.lobes = set.settings.lobes;
    z.values = decode(file, m, 0, per);
    set.mean = std::move(z);
  }
  return set;
}

}  // namespace matlas::zonal
