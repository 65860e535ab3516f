#include "core/blas.h"

#include <cctype>
#include <cstddef>
#include <cstdlib>
#include <dlfcn.h>

#include "core/cpu_features.h"
#include "core/error.h"

namespace matlas::blas {

namespace {

constexpr const char* kSoname = "libopenblas.so.0";
constexpr const char* kCoreVariable = "OPENBLAS_CORETYPE";

template <typename F>
void bind(void* handle, const char* name, F& f) {
  f = reinterpret_cast<F>(::dlsym(handle, name));
  if (f == nullptr)
    throw Error(std::string("OpenBLAS (") + kSoname + ") has no routine " + name + "; matlas needs Debian's libopenblas0");
}

Library load() {
  // OPENBLAS_CORETYPE is read once, by the library's initialiser during dlopen.
  const std::string kernel = std::getenv(kCoreVariable) ? "" : kernel_for_this_processor();
  if (!kernel.empty()) ::setenv(kCoreVariable, kernel.c_str(), 0);
  void* handle = ::dlopen(kSoname, RTLD_NOW | RTLD_LOCAL);
  const char* error = handle ? nullptr : ::dlerror();
  if (!kernel.empty()) ::unsetenv(kCoreVariable);
  if (handle == nullptr)
    throw Error(std::string("cannot load OpenBLAS (") + kSoname + "): " + (error ? error : "unknown error") +
                "; install Debian's libopenblas0");
  Library lib{};
  bind(handle, "cblas_dgemm", lib.dgemm);
  bind(handle, "cblas_dsyrk", lib.dsyrk);
  bind(handle, "cblas_ssyrk", lib.ssyrk);
  bind(handle, "cblas_dsymm", lib.dsymm);
  bind(handle, "cblas_dtrmm", lib.dtrmm);
  bind(handle, "cblas_dtrsm", lib.dtrsm);
  bind(handle, "dtrtri_", lib.dtrtri);
  bind(handle, "dlauum_", lib.dlauum);
  bind(handle, "dpotrf_", lib.dpotrf);
  bind(handle, "dsyevd_", lib.dsyevd);
  bind(handle, "openblas_get_corename", lib.corename);
  bind(handle, "openblas_get_config", lib.config);
  decltype(&openblas_set_num_threads) set_num_threads = nullptr;
  bind(handle, "openblas_set_num_threads", set_num_threads);
  set_num_threads(1);
  return lib;  // the handle stays open for the life of the process
}

}  // namespace

const Library& openblas() {
  static const Library lib = load();
  return lib;
}

// [A 0; C D]^-1 = [A^-1 0; -D^-1 C A^-1 D^-1].
int invert_lower_triangle(int n, double* a, int lda) {
  const Library& lib = openblas();
  constexpr int kLeaf = 16;
  int info = 0;
  if (n <= kLeaf) {
    lib.dtrtri("L", "N", &n, a, &lda, &info);
    return info;
  }
  const int h = n / 2, m = n - h;
  double* c = a + h;                                    // m x h below A
  double* d = a + h + static_cast<std::ptrdiff_t>(h) * lda;  // m x m
  if ((info = invert_lower_triangle(h, a, lda)) != 0) return info;
  if ((info = invert_lower_triangle(m, d, lda)) != 0) return info + h;
  lib.dtrmm(CblasColMajor, CblasRight, CblasLower, CblasNoTrans, CblasNonUnit, m, h, 1.0, a, lda, c, lda);
  lib.dtrmm(CblasColMajor, CblasLeft, CblasLower, CblasNoTrans, CblasNonUnit, m, h, -1.0, d, lda, c, lda);
  return 0;
}

int inverse_from_cholesky(int n, double* a, int lda) {
  const Library& lib = openblas();
  const int info = invert_lower_triangle(n, a, lda);
  if (info != 0) return info;
  int lauum_info = 0;
  lib.dlauum("L", &n, a, &lda, &lauum_info);  // L^-T L^-1
  return lauum_info;
}

std::string kernel_for(bool avx512, bool avx2_fma) {
  if (avx512) return "SkylakeX";
  if (avx2_fma) return "Haswell";
  return "";
}

std::string kernel_for_this_processor() { return kernel_for(cpu_has_avx512_skx(), cpu_has_avx2_fma()); }

std::string kernel_override_note(const char* user_choice, const std::string& wanted) {
  if (user_choice == nullptr || wanted.empty()) return "";
  const auto lower = [](std::string v) {
    for (char& c : v) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return v;
  };
  if (lower(user_choice) == lower(wanted)) return "";
  return std::string("OPENBLAS_CORETYPE=") + user_choice +
         " in the environment chose these kernels; on this processor matlas would run the " + wanted +
         " kernels (docs/BENCHMARKS.md compares them): unset the variable to let it choose";
}

std::string kernel_override_note() {
  return kernel_override_note(std::getenv(kCoreVariable), kernel_for_this_processor());
}

std::string description() { return openblas().config(); }

}  // namespace matlas::blas
