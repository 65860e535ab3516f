// The download endpoints of the API (docs/API.md): any map point or model material as a file
// for another renderer or an artist's tool. POST /api/export writes the table (MERL .binary, or
// RGL .bsdf for Mitsuba 3 and pbrt-v4: formats/rgl_bsdf_writer.h); POST /api/fit answers the
// analytic fit's report (artist/fit_report.h, with its error) before anything is downloaded,
// and POST /api/fit/file the fitted material as glTF, MaterialX or a Blender script; with "model":
// "principled-v1", the fit of Blender 2.8-3.6's Principled BSDF and its script. The bytes are those
// `matlas export` and `matlas fit` write for the same point or material.
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>

#include "artist/blender_snippet.h"
#include "artist/fit_error.h"
#include "artist/fit_report.h"
#include "artist/gltf_material.h"
#include "artist/materialx_document.h"
#include "artist/pbr_fit.h"
#include "formats/merl_file.h"
#include "formats/rgl_bsdf_writer.h"
#include "formats/tensor_file.h"
#include "manifold/export.h"
#include "server/api.h"
#include "server/http_error.h"

namespace matlas::server {

/// What a download is made of: the table of a point or a material and how the files name it.
struct Api::ExportSubject {
  Eigen::VectorXd x;
  std::optional<int> material;
  bool principled_v1 = false;  ///< the fit: Blender 2.8-3.6's Principled BSDF (else glTF's model)
  std::string key;       ///< the fit cache's key
  std::string name;      ///< the material's name in the files (as `matlas fit`'s default)
  std::string source;    ///< what it is, as `matlas export` / `matlas fit` say it
  std::string filename;  ///< the download's name, without extension
};

struct Api::FittedPoint {
  std::optional<artist::PbrFitResult> gltf;
  std::optional<artist::PrincipledV1FitResult> principled_v1;
  nlohmann::json report;
};

namespace {

/// A number as the shortest text that reads back the same (JSON's, and JavaScript's String()).
std::string shortest(double v) { return nlohmann::json(v).dump(); }

/// A file name from a material name: letters, digits, '.', '-' and '_' kept, others '_'.
std::string file_safe(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                      c == '-' || c == '_';
    out += keep ? c : '_';
  }
  return out.empty() || out[0] == '.' ? "matlas" + out : out;
}

Reply download(std::string bytes, const std::string& content_type, const std::string& filename) {
  Reply r = Reply::bytes(std::move(bytes), content_type);
  r.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + filename + "\"");
  return r;
}

}  // namespace

Api::ExportSubject Api::export_subject(const nlohmann::json& j) const {
  ExportSubject s;
  s.x = parse_latent(j, "x", domain_);
  s.principled_v1 = parse_choice(j, "model", {"gltf", "principled-v1"}, "gltf") == "principled-v1";
  const std::string model_key = s.principled_v1 ? " principled-v1" : " gltf";
  const std::string model_file = model_.path().filename().string();
  if (j.contains("material") && !j["material"].is_null()) {
    const int i = parse_int(j, "material", 0, model_.count() - 1, 0);
    s.material = i;
    s.name = model_.names()[static_cast<std::size_t>(i)];
    s.source = "material " + s.name + " of " + model_file;
    s.filename = file_safe(s.name);
    s.key = "material " + std::to_string(i) + model_key;
    return s;
  }
  std::string at;
  s.filename = "matlas";
  char buf[32];
  for (Eigen::Index i = 0; i < s.x.size(); ++i) {
    if (i > 0) at += ',';
    at += shortest(s.x[i]);
    std::snprintf(buf, sizeof buf, "_%.4f", s.x[i]);
    s.filename += buf;
  }
  s.name = "matlas point " + at;
  s.source = "x = " + at + " of " + model_file;
  s.key = "x " + point_key(s.x) + model_key;
  return s;
}

BrdfTable Api::subject_table(const ExportSubject& s, ExportStats* stats) const {
  const Eigen::VectorXd w = s.material ? model_.material_weights(*s.material) : weights_at(s.x);
  return export_table(model_, w, stats);  // negative values clamped to 0
}

Reply Api::export_file(const std::string& body) {
  const auto j = parse_json_object(body);
  const std::string format = parse_choice(j, "format", {"binary", "bsdf", "bsdf-spectral"}, "binary");
  const ExportSubject s = export_subject(j);
  std::string bytes;
  ExportStats stats;
  {
    auto slot = acquire(heavy_);
    const BrdfTable table = subject_table(s, &stats);
    if (format == "binary") {
      bytes = encode_merl(table);
    } else {
      RglExportOptions options = options_.bsdf_export;
      options.description = "matlas export of " + s.source;  // as `matlas export -o X.bsdf` writes it
      if (format == "bsdf-spectral") options.wavelengths = kSpectralExportWavelengths;
      const std::vector<std::byte> file = serialize_tensor_file(rgl_fields_from_table(table, options));
      bytes.assign(reinterpret_cast<const char*>(file.data()), file.size());
    }
  }
  Reply r = download(std::move(bytes), "application/octet-stream", s.filename + (format == "binary" ? ".binary" : ".bsdf"));
  r.headers.emplace_back("X-Matlas-Clamped", std::to_string(stats.clamped));
  return r;
}

std::shared_ptr<const Api::FittedPoint> Api::fitted(const ExportSubject& s) {
  {
    std::lock_guard lock(fits_mutex_);
    for (const auto& [key, f] : fits_)
      if (key == s.key) return f;
  }
  auto f = std::make_shared<FittedPoint>();
  {
    auto slot = acquire(heavy_);
    const BrdfTable table = subject_table(s, nullptr);
    const auto start = std::chrono::steady_clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const std::optional<double> variance = s.material ? std::nullopt : std::optional(model_.variance(s.x));
    if (s.principled_v1) {
      const auto& fit = f->principled_v1.emplace(artist::fit_principled_v1(table));
      const double took = seconds();
      f->report = artist::fit_report_json(s.source, fit, artist::fit_error(table, fit.model), took, variance);
    } else {
      const auto& fit = f->gltf.emplace(artist::fit_gltf_pbr(table));
      const double took = seconds();
      f->report = artist::fit_report_json(s.source, fit, artist::fit_error(table, fit.model), took, variance);
    }
  }
  f->report["name"] = s.name;
  std::lock_guard lock(fits_mutex_);
  fits_.emplace_back(s.key, f);
  if (fits_.size() > kFitsKept) fits_.erase(fits_.begin());
  return f;
}

Reply Api::fit(const std::string& body) {
  const ExportSubject s = export_subject(parse_json_object(body));
  return Reply::json(fitted(s)->report);
}

Reply Api::fit_file(const std::string& body) {
  const auto j = parse_json_object(body);
  if (!j.contains("format") || j["format"].is_null())
    throw bad_request("\"format\" is missing: one of \"gltf\", \"mtlx\", \"py\"");
  const std::string format = parse_choice(j, "format", {"gltf", "mtlx", "py"}, "gltf");
  const ExportSubject s = export_subject(j);
  if (s.principled_v1 && format != "py")
    throw bad_request("\"format\": " + format + " has no Blender 2.8-3.6 Principled BSDF; \"model\": \"principled-v1\" "
                      "is for \"py\" (a Blender script)");
  const std::shared_ptr<const FittedPoint> f = fitted(s);
  // One content type for the three, as for every download (docs/api.schema.json): the file's
  // kind is in its name.
  std::string text;
  if (s.principled_v1) {
    text = artist::blender_snippet(f->principled_v1->model, s.name, s.source);
  } else {
    const GltfPbr& m = f->gltf->model;
    text = format == "gltf"   ? artist::gltf_material_document(m, s.name, s.source)
           : format == "mtlx" ? artist::materialx_document(m, s.name, s.source)
                              : artist::blender_snippet(m, s.name, s.source);
  }
  return download(text, "application/octet-stream", s.filename + (s.principled_v1 ? "-blender3" : "") + "." + format);
}

}  // namespace matlas::server
