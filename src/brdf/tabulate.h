#pragma once
// Tabulation of a BRDF functor onto the MERL half/difference grid.
//
// Each bin holds f at its centre (bin_centre, phi_h = 0, turned into directions by
// from_half_diff). Bins whose centre has wi or wo at or below the horizon (z <= 0) hold 0, not
// MERL's -1: -1 means "not measured", whereas an analytic BRDF is known to be 0 there, so the whole
// table counts as measured. A table never contains NaN or infinities: a non-finite value throws.
#include <functional>

#include "brdf/brdf_table.h"

namespace matlas {

/// Type-erased BRDF: f(wi, wo) -> Rgb (physical units), local frame, normal +z.
using BrdfFunction = std::function<Rgb(const Vec3& wi, const Vec3& wo)>;

/// Tabulates `f` (called concurrently from several threads: it must be thread-safe) on `dims`.
/// Throws matlas::Error if f returns a negative, NaN or infinite value.
BrdfTable tabulate_function(const BrdfFunction& f, MerlDims dims = {});

/// Tabulates any functor f(wi, wo) -> Rgb (e.g. an analytic BRDF of brdf/analytic.h).
template <class F>
BrdfTable tabulate(const F& f, MerlDims dims = {}) {
  return tabulate_function(BrdfFunction([&f](const Vec3& wi, const Vec3& wo) { return Rgb(f(wi, wo)); }),
                           dims);
}

}  // namespace matlas
