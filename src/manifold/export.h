#pragma once
// Exporting a point of the map as a MERL table for other renderers.
//
// m(x) is a signed combination of the inputs, so it can dip below zero where the inputs differ
// a lot (far from the data, or between very different lobes). A BRDF cannot be negative and MERL
// readers take negative values for "no measurement", so the export clamps them to 0 and counts
// them. Dropped columns (not measured in every input) are written as -1, as MERL does.
#include <cstddef>

#include "manifold/model.h"

namespace matlas {

struct ExportStats {
  std::size_t clamped = 0;   ///< negative interpolated values set to 0
  std::size_t missing = 0;   ///< dropped columns written as missing
  double most_negative = 0;  ///< the most negative value before clamping
};

/// The table of weights w, clamped as described above.
BrdfTable export_table(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& w,
                       ExportStats* stats = nullptr);

}  // namespace matlas
