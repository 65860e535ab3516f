#pragma once
// Invariants. matlas::Error (core/error.h) is for what a user's input can cause: a bad file, a
// flag out of range. MATLAS_CHECK is for what must never happen whatever the input: a shape that
// the code itself made, a weight vector of the wrong length, a non-finite value where the maths
// cannot produce one. A failed check is a bug in matlas; it throws matlas::InternalError, whose
// message gives the source position, the condition and the values ("internal check failed at
// render/image_basis.cpp:120: weights.size() == count() (4 vs 5)"). The command prints it as an
// internal error, the server answers 500 and lives on.
//
//   MATLAS_CHECK(cond) / MATLAS_CHECK(cond, "what it means")   always on (cheap checks)
//   MATLAS_CHECK_EQ(a, b), _NE, _LT, _LE, _GT, _GE              always on; print both values
//   MATLAS_DCHECK(cond), MATLAS_DCHECK_EQ(a, b), ...            on in Debug and sanitizer builds
//                                                               (MATLAS_DCHECKS defined), for
//                                                               checks inside hot loops
// The arguments of a disabled DCHECK are compiled but never evaluated.
#include <stdexcept>
#include <string>
#include <type_traits>

namespace matlas {

class InternalError : public std::logic_error {
public:
  using std::logic_error::logic_error;
};

/// Throws InternalError for a failed check at file:line.
[[noreturn]] void check_failed(const char* file, int line, const char* condition, const std::string& detail);

namespace check_detail {

// Appends rather than `"(" + text`: GCC 12 warns falsely (-Wrestrict) on that form when inlined.
inline std::string message() { return {}; }
inline std::string message(const std::string& text) {
  std::string out(1, '(');
  out.append(text).push_back(')');
  return out;
}

template <class T>
std::string value(const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
  else if constexpr (std::is_arithmetic_v<T>) return std::to_string(v);
  else if constexpr (std::is_enum_v<T>) return std::to_string(static_cast<std::underlying_type_t<T>>(v));
  else return "?";
}

template <class A, class B>
std::string values(const A& a, const B& b) {
  std::string out(1, '(');
  out.append(value(a)).append(" vs ").append(value(b)).push_back(')');
  return out;
}

}  // namespace check_detail
}  // namespace matlas

#define MATLAS_CHECK(condition, ...)                                                                     \
  do {                                                                                                   \
    if (!(condition)) [[unlikely]]                                                                       \
      ::matlas::check_failed(__FILE__, __LINE__, #condition, ::matlas::check_detail::message(__VA_ARGS__)); \
  } while (0)

#define MATLAS_CHECK_OP(a, op, b)                                                                        \
  do {                                                                                                   \
    const auto& matlas_check_a_ = (a);                                                                   \
    const auto& matlas_check_b_ = (b);                                                                   \
    if (!(matlas_check_a_ op matlas_check_b_)) [[unlikely]]                                              \
      ::matlas::check_failed(__FILE__, __LINE__, #a " " #op " " #b,                                      \
                             ::matlas::check_detail::values(matlas_check_a_, matlas_check_b_));          \
  } while (0)

#define MATLAS_CHECK_EQ(a, b) MATLAS_CHECK_OP(a, ==, b)
#define MATLAS_CHECK_NE(a, b) MATLAS_CHECK_OP(a, !=, b)
#define MATLAS_CHECK_LT(a, b) MATLAS_CHECK_OP(a, <, b)
#define MATLAS_CHECK_LE(a, b) MATLAS_CHECK_OP(a, <=, b)
#define MATLAS_CHECK_GT(a, b) MATLAS_CHECK_OP(a, >, b)
#define MATLAS_CHECK_GE(a, b) MATLAS_CHECK_OP(a, >=, b)

#ifdef MATLAS_DCHECKS
#define MATLAS_DCHECK(condition, ...) MATLAS_CHECK(condition __VA_OPT__(, ) __VA_ARGS__)
#define MATLAS_DCHECK_EQ(a, b) MATLAS_CHECK_EQ(a, b)
#define MATLAS_DCHECK_LT(a, b) MATLAS_CHECK_LT(a, b)
#define MATLAS_DCHECK_LE(a, b) MATLAS_CHECK_LE(a, b)
#else
#define MATLAS_DCHECK(condition, ...) \
  do {                                \
    if (false) (void)(condition);     \
  } while (0)
#define MATLAS_DCHECK_EQ(a, b) MATLAS_DCHECK((a) == (b))
#define MATLAS_DCHECK_LT(a, b) MATLAS_DCHECK((a) < (b))
#define MATLAS_DCHECK_LE(a, b) MATLAS_DCHECK((a) <= (b))
#endif
