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
