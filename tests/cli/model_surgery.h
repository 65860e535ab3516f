#pragma once
// Test helper: rewrites the matlas metadata of a model file in place (the header keeps its length:
// a build reserves generous padding), to craft models whose metadata lies about the tensors.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
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

/// Replaces the matlas metadata of a model file with `text` (any JSON text, of any length): the
/// header is written again with its new length (padded so the data stays 64-byte aligned) and the
/// tensors copied after it.
inline void replace_model_metadata_text(const std::filesystem::path& path, const std::string& text) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t length = 0;
  in.read(reinterpret_cast<char*>(&length), 8);
  std::string header_text(length, ' ');
  in.read(header_text.data(), static_cast<std::streamsize>(length));
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  nlohmann::json header = nlohmann::json::parse(header_text);
  header["__metadata__"]["matlas"] = text;
  std::string out = header.dump();
  out.resize((out.size() + 8 + 63) / 64 * 64 - 8, ' ');
  const std::uint64_t new_length = out.size();
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(&new_length), 8);
  f.write(out.data(), static_cast<std::streamsize>(out.size()));
  f.write(data.data(), static_cast<std::streamsize>(data.size()));
}

}  // namespace matlas::test
