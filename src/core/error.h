#pragma once
// matlas::Error: the one exception type for bad input and failed operations. Its message is meant
// for the user: it names the file (or argument) and says what is wrong with it.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace matlas {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Error about a file: "PATH: what".
inline Error file_error(const std::filesystem::path& path, const std::string& what) {
  return Error(path.string() + ": " + what);
}

}  // namespace matlas
