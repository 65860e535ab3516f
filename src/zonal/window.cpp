#include "zonal/window.h"

#include <cmath>

#include "brdf/types.h"
#include "core/error.h"

namespace matlas::zonal {

std::vector<double> band_window(BandWindow window, int shown) {
  if (shown < 0 || shown > 1024) throw Error("band window: bands must be between 0 and 1024, got " + std::to_string(shown));
  std::vector<double> w(static_cast<std::size_t>(shown) + 1, 1.0);
  const double n = shown + 1.0;
  for (int l = 1; l <= shown; ++l) {
    double v = 1.0;
    switch (window) {
      case BandWindow::none: break;
      case BandWindow::hann: {
        const double c = std::cos(kPi * l / (2.0 * n));
        v = c * c;
        break;
      }
      case BandWindow::lanczos: {
        const double x = kPi * l / n;
        v = std::sin(x) / x;
        break;
      }
      case BandWindow::gauss: {
        const double s = n / 2.5;
        v = std::exp(-l * (l + 1.0) / (2.0 * s * s));
        break;
      }
      case BandWindow::taper: {
        const double h = n / 2.0;
        if (l > h) {
          const double c = std::cos(kPi * (l - h) / (2.0 * (n - h)));
          v = c * c;
        }
        break;
      }
    }
    w[static_cast<std::size_t>(l)] = v;
  }
  return w;
}

BandWindow parse_band_window(const std::string& name) {
  if (name == "none") return BandWindow::none;
  if (name == "hann") return BandWindow::hann;
  if (name == "lanczos") return BandWindow::lanczos;
  if (name == "gauss") return BandWindow::gauss;
  if (name == "taper") return BandWindow::taper;
  throw Error("unknown band window '" + name + "' (none, hann, lanczos, gauss, taper)");
}

const char* band_window_name(BandWindow window) {
  switch (window) {
    case BandWindow::none: return "none";
    case BandWindow::hann: return "hann";
    case BandWindow::lanczos: return "lanczos";
    case BandWindow::gauss: return "gauss";
    case BandWindow::taper: return "taper";
  }
  return "none";
}

}  // namespace matlas::zonal
