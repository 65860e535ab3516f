#include "manifold/interpolation.h"

#include "core/error.h"

namespace matlas {

const char* to_string(Interpolation mode) { return mode == Interpolation::convex ? "convex" : "gp"; }

Interpolation interpolation_from_string(const std::string& name) {
  if (name == "convex") return Interpolation::convex;
  if (name == "gp") return Interpolation::gp;
  throw Error("unknown interpolation mode '" + name + "' (valid: convex, gp)");
}

}  // namespace matlas
