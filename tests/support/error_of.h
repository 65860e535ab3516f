#pragma once
// The message of the matlas::Error a call throws, or "no error": for tests of error messages.
#include <functional>
#include <string>

#include "core/error.h"

namespace matlas::test {

inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace matlas::test
