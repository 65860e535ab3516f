#pragma once
// The inner loop of every model query: the dot product of one column's n stored (float) values
// with the weights w (double), accumulated in double. Compiled for AVX-512, AVX2 and baseline
// x86-64, picked at run time (GCC function multi-versioning), so one binary is fast everywhere.
namespace matlas {

double dot_f32_f64(const float* values, const double* weights, int n);

}  // namespace matlas
