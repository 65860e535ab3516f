#include <chrono>
#include <cstring>
#include <fstream>
#include <tuple>

#include <gtest/gtest.h>

#include "core/error.h"
#include "formats/rgl_bsdf.h"
#include "formats/tensor_file.h"
#include "rgl_test_files.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

std::string parse_error(std::span<const std::byte> bytes, const std::string& name = "x.bsdf") {
  try {
    TensorFile::parse(bytes, name);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(TensorFile, RoundTrip) {
  const std::vector<float> values{1.5f, -2.0f, 3.25f, 0.0f, 7.0f, 8.0f};
  const std::uint8_t flag[1] = {1};
  const std::vector<TensorField> fields{float32_field("a", {2, 3}, values), uint8_field("flag", {1}, flag)};
  const std::vector<std::byte> bytes = serialize_tensor_file(fields);
  const TensorFile f = TensorFile::parse(bytes, "mem.bsdf");
  ASSERT_EQ(f.fields().size(), 2u);
  const TensorField& a = f.field("a");
  EXPECT_EQ(a.dtype, TensorType::Float32);
  EXPECT_EQ(a.shape, (std::vector<std::uint64_t>{2, 3}));
  EXPECT_EQ(a.describe(), "float32 [2, 3]");
  ASSERT_EQ(a.data.size(), values.size() * 4);
  EXPECT_EQ(0, std::memcmp(a.data.data(), values.data(), a.data.size()));
  EXPECT_EQ(static_cast<std::uint8_t>(f.field("flag").data[0]), 1);
  EXPECT_EQ(f.find("missing"), nullptr);

  test::TempDir dir;
  write_tensor_file(dir / "t.bsdf", fields);
  const TensorFile g = TensorFile::read(dir / "t.bsdf");
  EXPECT_EQ(g.field("a").data, a.data);
}

TEST(TensorFile, MissingFieldNamesTheFileAndListsTheFields) {
  const std::uint8_t flag[1] = {1};
  const auto bytes = serialize_tensor_file({uint8_field("flag", {1}, flag)});
  const TensorFile f = TensorFile::parse(bytes, "m.bsdf");
  try {
    f.field("vndf", "RGL");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("m.bsdf: no field 'vndf'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("flag"), std::string::npos) << e.what();
  }
}

TEST(TensorFile, EveryTruncationIsRejectedWithTheFileName) {
  const auto bytes = serialize_tensor_file(test::SyntheticRgl{}.fields());
  // Every prefix shorter than the whole file fails (the last field's data ends at the end).
  ASSERT_FALSE(TensorFile::parse(bytes, "w.bsdf").fields().empty());
  for (std::size_t n = 0; n < bytes.size(); n += (n < 600 ? 1 : 97)) {
    const std::string e = parse_error(std::span(bytes.data(), n), "cut.bsdf");
    EXPECT_EQ(e.rfind("cut.bsdf: ", 0), 0u) << n << ": " << e;
    const char* want = n == 0 ? "empty" : n < 12 ? "not a tensor file" : "truncated";
    EXPECT_NE(e.find(want), std::string::npos) << n << ": " << e;
  }
}

TEST(TensorFile, CorruptHeadersAreRejected) {
  auto bytes = serialize_tensor_file(test::SyntheticRgl{}.fields());
  EXPECT_NE(parse_error({}).find("empty"), std::string::npos);
  auto bad = bytes;
  bad[0] = std::byte{'X'};
  EXPECT_NE(parse_error(bad).find("not a tensor file"), std::string::npos);
  bad = bytes;
  bad[12] = std::byte{2};  // version 2.0
  EXPECT_NE(parse_error(bad).find("unsupported tensor file version 2.0"), std::string::npos);
  bad = bytes;
  std::memset(bad.data() + 14, 0, 4);  // zero fields
  EXPECT_NE(parse_error(bad).find("0 fields"), std::string::npos);
  // First field: name length 11 ("description"), then rank (2 bytes), then the dtype byte.
  bad = bytes;
  bad[18 + 2 + 11 + 2] = std::byte{42};
  EXPECT_NE(parse_error(bad).find("unknown dtype code 42"), std::string::npos) << parse_error(bad);
  // Its offset pointing past the end.
  bad = bytes;
  const std::uint64_t far = bytes.size() + 1000;
  std::memcpy(bad.data() + 18 + 2 + 11 + 2 + 1, &far, 8);
  EXPECT_NE(parse_error(bad).find("field 'description'"), std::string::npos) << parse_error(bad);
  EXPECT_NE(parse_error(bad).find("past the end"), std::string::npos);
  // An absurd shape.
  bad = bytes;
  const std::uint64_t huge = ~0ull;
  std::memcpy(bad.data() + 18 + 2 + 11 + 2 + 1 + 8, &huge, 8);
  EXPECT_NE(parse_error(bad).find("field 'description'"), std::string::npos) << parse_error(bad);
}

TEST(TensorFile, DuplicateFieldNamesAreRejected) {
  const std::uint8_t one[1] = {1};
  const auto bytes = serialize_tensor_file({uint8_field("a", {1}, one), uint8_field("a", {1}, one)});
  EXPECT_NE(parse_error(bytes).find("two fields named 'a'"), std::string::npos);
}

/// A header of one field (name, dtype code, offset, shape) and nothing else.
std::vector<std::byte> header_only(const std::vector<std::tuple<std::string, std::uint8_t, std::uint64_t,
                                                                std::vector<std::uint64_t>>>& fields) {
  std::vector<std::byte> out;
  auto put = [&out](const void* p, std::size_t n) {
    out.insert(out.end(), static_cast<const std::byte*>(p), static_cast<const std::byte*>(p) + n);
  };
  put("tensor_file", 12);
  const std::uint8_t version[2] = {1, 0};
  put(version, 2);
  const auto count = static_cast<std::uint32_t>(fields.size());
  put(&count, 4);
  for (const auto& [name, type, offset, shape] : fields) {
    const auto length = static_cast<std::uint16_t>(name.size());
    put(&length, 2);
    put(name.data(), name.size());
    const auto rank = static_cast<std::uint16_t>(shape.size());
    put(&rank, 2);
    put(&type, 1);
    put(&offset, 8);
    put(shape.data(), 8 * shape.size());
  }
  return out;
}

TEST(TensorFile, HugeSparseFilesAreRefusedBeforeTheirDataIsRead) {
  // 2 GiB of apparent size, a few bytes on disk: one float32 field of 2^29 values. Used to be
  // read whole (minutes, several GiB of memory) before anything was refused.
  test::TempDir dir;
  const auto header = header_only({{"rgb", 10, 64, {std::uint64_t{1} << 29}}});
  {
    std::ofstream out(dir / "sparse.bsdf", std::ios::binary);
    out.write(reinterpret_cast<const char*>(header.data()), static_cast<std::streamsize>(header.size()));
  }
  std::filesystem::resize_file(dir / "sparse.bsdf", 64 + (std::uint64_t{1} << 31));
  const auto start = std::chrono::steady_clock::now();
  try {
    TensorFile::read(dir / "sparse.bsdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("sparse.bsdf: 2147483712 bytes: larger than any RGL tensor file (.bsdf) "
                                         "could be (at most 1024 MiB are read)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(TensorFile, ShapesAreBoundedByTheFileAndFieldsMayNotShareBytes) {
  // A zero extent used to hide any other: [0, 2^62] passed as 0 values.
  auto bytes = header_only({{"a", 1, 64, {0, std::uint64_t{1} << 62}}});
  bytes.resize(128);
  EXPECT_NE(parse_error(bytes).find("x.bsdf: invalid tensor file: field 'a' has an absurd shape uint8 [0, "
                                    "4611686018427387904] for a file of 128 bytes"),
            std::string::npos)
      << parse_error(bytes);
  // Four fields of 4 KiB over the same 4 KiB: 16 KiB of memory from a 4 KiB file (and 4096 such
  // fields, 16 MiB from 4 KiB).
  bytes = header_only({{"a", 1, 256, {4096}}, {"b", 1, 256, {4096}}, {"c", 1, 256, {4096}}, {"d", 1, 256, {4096}}});
  bytes.resize(256 + 4096);
  EXPECT_NE(parse_error(bytes).find("x.bsdf: invalid tensor file: its fields claim 16384 bytes of data, more than the"),
            std::string::npos)
      << parse_error(bytes);
  bytes = header_only({{"a", 1, 256, {4096}}});
  bytes.resize(256 + 4096);
  EXPECT_EQ(parse_error(bytes), "no error");
}

TEST(TensorFile, HeadersLongerThanTheFirstReadAreReadWhole) {
  // The header is read from the file's first 64 KiB, and more when it goes on: two names of
  // 60000 bytes make a header of 120 KiB.
  const std::uint8_t one[1] = {7};
  const std::vector<TensorField> fields{uint8_field(std::string(60000, 'a'), {1}, one),
                                        uint8_field(std::string(60000, 'b'), {1}, one)};
  test::TempDir dir;
  write_tensor_file(dir / "long.bsdf", fields);
  const TensorFile f = TensorFile::read(dir / "long.bsdf");
  ASSERT_EQ(f.fields().size(), 2u);
  EXPECT_EQ(static_cast<int>(f.field(std::string(60000, 'b')).data.at(0)), 7);
  // A header cut inside its second name, past the first 64 KiB: truncated (fields of no data
  // at offset 0, so that the cut is found in the header and not past a field's data).
  const auto header = header_only({{std::string(60000, 'a'), 1, 0, {0}}, {std::string(60000, 'b'), 1, 0, {0}}});
  auto cut = header;
  cut.resize(90000);
  {
    std::ofstream out(dir / "cut.bsdf", std::ios::binary);
    out.write(reinterpret_cast<const char*>(cut.data()), static_cast<std::streamsize>(cut.size()));
  }
  const std::string e = test::error_of([&] { TensorFile::read(dir / "cut.bsdf"); });
  EXPECT_NE(e.find("cut.bsdf: truncated tensor file: the header ends inside a field name (90000 bytes)"),
            std::string::npos)
      << e.substr(0, 300);
  {
    std::ofstream out(dir / "whole.bsdf", std::ios::binary);
    out.write(reinterpret_cast<const char*>(header.data()), static_cast<std::streamsize>(header.size()));
  }
  EXPECT_EQ(TensorFile::read(dir / "whole.bsdf").fields().size(), 2u);
}

TEST(TensorFile, MissingFileAndDirectory) {
  test::TempDir dir;
  try {
    TensorFile::read(dir / "none.bsdf");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("none.bsdf: no such file"), std::string::npos);
  }
  EXPECT_THROW(TensorFile::read(dir.path()), Error);
}

}  // namespace
}  // namespace matlas
