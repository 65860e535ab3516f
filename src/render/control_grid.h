#pragma once
// ControlGrid: a control variate's smooth integral tabulated over an image (render/render.h).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/progress.h"
#include "render/control_variate.h"
#include "render/scene.h"

namespace matlas::render {

/// A control variate's smooth integral (ControlVariate::smooth_integral) tabulated over an image,
/// computed once for many renders of that size: render() interpolates it bilinearly at each
/// camera sample instead of evaluating it there (an error of second order in the spacing,
/// measured in docs/RENDERING.md "Control variate"). A pixel whose corners see the object at
/// cos(theta_o) >= kControlGridCosine with normals within kControlGridAngle is one cell; where the
/// view grazes or the normal turns faster it is cut into up to kControlGridMaxSubdivisions^2
/// cells; a pixel that does not see only the object (the silhouette) or whose normals turn more
/// than that (a crease, an edge in front of another surface) renders without the control variate.
struct ControlGrid {
  struct Cell {
    int subdivisions = 0;     ///< s per side (0: no control variate in this pixel)
    std::size_t offset = 0;   ///< its (s + 1)^2 values, row-major, in `values`
  };
  int width = 0, height = 0;  ///< the image's
  std::vector<Cell> cells;    ///< per pixel, row-major
  std::vector<Rgb> values;
};
inline constexpr double kControlGridCosine = 0.3;
inline constexpr double kControlGridAngle = 0.035;  ///< radians (2 degrees) of normal turn per cell
inline constexpr int kControlGridMaxSubdivisions = 8;

/// The grid of a width x height image of the scene through its camera (the corners' and cells'
/// rays as render() casts them), reporting rows to `progress` (which may throw to stop it). Throws
/// matlas::Error for sizes outside 1..16384.
ControlGrid control_grid(const Scene& scene, int width, int height, const ControlVariate& control,
                         ProgressSink& progress = null_progress());

}  // namespace matlas::render
