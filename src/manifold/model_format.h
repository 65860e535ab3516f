#pragma once
// Names and version of the `.matlas` model file (a safetensors file; docs/MODEL_FORMAT.md).
namespace matlas {

/// Number of albedo-curve samples stored per material: theta_o at bin centres of 90 uniform
/// bins over [0, 90) degrees (the `albedo` tensor's middle dimension).
inline constexpr int kAlbedoAngles = 90;

}  // namespace matlas

namespace matlas::model_format {

inline constexpr const char* kFormatName = "matlas-model";
inline constexpr int kVersion = 2;
/// Key of the JSON metadata string in the safetensors "__metadata__" map.
inline constexpr const char* kMetadataKey = "matlas";
/// Deepest nesting of arrays and objects accepted in the metadata JSON (a model's own is 3 deep):
/// deeper is a crafted file, refused on open, since recursive JSON code (dump(), a fingerprint)
/// would overflow the stack on it.
inline constexpr int kMaxMetadataDepth = 64;

/// Whether [theta_h, theta_d, phi_d] bin counts are a MERL grid as models store it: phi_d twice
/// theta_d (theta_d over [0, 90) and phi_d over [0, 180) degrees in equal steps), so that a grid
/// given in another order is refused.
inline constexpr bool is_model_grid(int theta_h, int theta_d, int phi_d) {
  return theta_h >= 1 && theta_d >= 1 && phi_d == 2 * theta_d;
}

// Tensors, in file order (largest element type first so every tensor is aligned).
inline constexpr const char* kLatent = "latent";            ///< F64 [n, q]
inline constexpr const char* kGram = "gram";                ///< F64 [n, n] centred Gram, linear data
/// F64 [n, n] centred Gram in the placement (layout) space: the metric of the convex
/// interpolation. Optional: models written before it existed use `gram`.
inline constexpr const char* kLayoutGram = "layout_gram";
inline constexpr const char* kAlbedo = "albedo";            ///< F64 [n, kAlbedoAngles, 3] albedo curves
inline constexpr const char* kMean = "mean";                ///< F32 [D'] mean of each kept column
inline constexpr const char* kValueColumn = "value_column"; ///< I32 [3 * bins] kept column or -1
inline constexpr const char* kData = "data";                ///< F32|F16 [D', n] column-interleaved inputs

}  // namespace matlas::model_format
