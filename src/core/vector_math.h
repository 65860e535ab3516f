#pragma once
// exp, expm1 and log over arrays, through glibc's vector math library (libmvec) where the
// processor has AVX-512 or AVX2: 8 or 4 values per call instead of one. The likelihood takes an
// exp per pair of latent points for the kernel and an expm1 and a log per pair for the repulsive
// prior; at n = 100 Eigen's exp (compiled for baseline x86-64, two doubles per instruction) was
// a fifth of an evaluation, and the prior's scalar expm1 and log a third of it at q = 5.
//
// glibc documents libmvec's functions to within 4 ulp (its scalar functions: under 1). Every
// caller of the kernel goes through exp_in_place, so the covariance matrix of the likelihood,
// the posterior's K and the query vectors k(x) stay consistent with each other on a machine.
#include <cstddef>

namespace matlas {

/// values[i] = exp(values[i]) for i < count.
void exp_in_place(double* values, std::size_t count);
/// values[i] = expm1(values[i]) = exp(values[i]) - 1, accurate near 0.
void expm1_in_place(double* values, std::size_t count);
/// values[i] = log(values[i]).
void log_in_place(double* values, std::size_t count);

}  // namespace matlas
