#pragma once
// Test helper: rewrites the matlas metadata of a model file in place (the header keeps its length:
// a build reserves generous padding), to craft models whose metadata lies about the tensors.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

namespace matlas::test {

inline void edit_model_metadata(const std::filesystem::path& path, const std::function<void(nlohmann::json&)>& edit) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  std::uint64_t length = 0;
  f.read(reinterpret_cast<char*>(&length), 8);
  std::string text(length, ' ');
  f.read(text.data(), static_cast<std::streamsize>(length));
  nlohmann::json header = nlohmann::json::parse(text);
  nlohmann::json meta = nlohmann::json::parse(header["__metadata__"]["matlas"].get<std::string>());
  edit(meta);
  header["__metadata__"]["matlas"] = meta.dump();
  std::string out = header.dump();
  if (out.size() > length) throw std::runtime_error("edited header does not fit");
  out.resize(length, ' ');
  f.seekp(8);
  f.write(out.data(), static_cast<std::streamsize>(out.size()));
}

}  // namespace matlas::test
