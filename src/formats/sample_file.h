#pragma once
// Sparse BRDF measurements ("sample files", docs/ACQUISITION.md): a handful of (incoming,
// outgoing, RGB) triples in the surface's frame, read from CSV or JSON, and the measurement plans
// `matlas sample-plan` writes in the same CSV with the values left empty.
//
// CSV: a header row naming the columns (any order, case-insensitive, unknown columns ignored,
// lines starting with '#' and blank lines skipped), then one sample per row:
//   directions  theta_i,phi_i,theta_o,phi_o (degrees)  or  wi_x,wi_y,wi_z,wo_x,wo_y,wo_z (normal +z;
//               normalised when read)
//   values      r,g,b; all three empty: a planned direction not measured yet
//   quantity    optional: "brdf" (the default: f, 1/sr) or "ratio" (f cos(theta_i), the ratio of
//               reflected radiance to incident irradiance along wi), converted to f when read
//   uncertainty optional: sigma (all channels) or sigma_r,sigma_g,sigma_b, one standard deviation
//               in the row's quantity; empty or 0: unknown
// JSON: {"samples": [{"theta_i":..,"phi_i":..,"theta_o":..,"phi_o":.. | "wi":[x,y,z],"wo":[x,y,z],
//        "rgb":[r,g,b] | null, "quantity":"brdf"|"ratio", "sigma": s | [r,g,b]}, ...]} (or the array
// alone); sample k is reported as "sample k".
//
// A row is invalid when a direction is at or below the horizon (theta >= 90 degrees or z <= 0),
// a value or direction is not finite, or a value or uncertainty is negative; every invalid row is
// reported with its line, and the read fails unless the caller skips them.
#include <filesystem>
#include <string>
#include <vector>

#include "brdf/types.h"

namespace matlas {

struct MeasuredSample {
  Vec3 wi = Vec3::UnitZ();  ///< unit, local frame (normal +z)
  Vec3 wo = Vec3::UnitZ();
  Rgb value = Rgb::Zero();  ///< BRDF value f (1/sr), whatever the row's quantity
  Rgb sigma = Rgb::Zero();  ///< uncertainty of f (1/sr); 0 where not given
  bool measured = false;    ///< false for a planned direction without values
  int line = 0;             ///< CSV line (1-based) or JSON sample number (1-based)
};

struct SampleFile {
  std::vector<MeasuredSample> samples;  ///< valid rows, measured or planned, in file order
  /// One line per invalid row skipped ("line 7: theta_i = 95 is below the horizon").
  std::vector<std::string> skipped;
  bool json = false;  ///< read from JSON (rows are "sample k", not "line k")
  /// The samples with values.
  std::vector<MeasuredSample> measured() const;
};

struct SampleReadOptions {
  /// Drop invalid rows (listed in SampleFile::skipped) instead of failing.
  bool skip_invalid = false;
};

/// Reads a CSV or JSON sample file (JSON when the first non-blank character is '{' or '[').
/// Throws matlas::Error naming the file and the line: unreadable file, missing direction columns,
/// a cell that is not a number, a row with some but not all of r,g,b, and (unless skipped)
/// invalid rows, the first ten listed with their lines and the rest counted.
SampleFile read_samples(const std::filesystem::path& path, const SampleReadOptions& options = {});
/// The same from text in memory; `name` stands for the file in messages.
SampleFile parse_samples(const std::string& text, const std::string& name,
                         const SampleReadOptions& options = {});

/// A unit direction's angles in degrees: theta from the normal +z, phi in [0, 360).
struct DirectionAngles {
  double theta = 0, phi = 0;
};
DirectionAngles direction_angles(const Vec3& w);

/// The CSV of a measurement plan (or of samples): theta_i,phi_i,theta_o,phi_o in degrees with
/// quantity "brdf", r,g,b and sigma_r,sigma_g,sigma_b (empty for samples not measured), preceded
/// by `comment` lines (each prefixed "# "). Angles are written with 6 decimals (a direction to
/// about 2e-8 rad).
std::string format_samples_csv(const std::vector<MeasuredSample>& samples,
                               const std::vector<std::string>& comment = {});

}  // namespace matlas
