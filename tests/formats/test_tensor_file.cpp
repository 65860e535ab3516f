#include <cstring>
#include <fstream>

#include <gtest/gtest.h>

#include "core/error.h"
#include "formats/rgl_bsdf.h"
#include "formats/tensor_file.h"
#include "rgl_test_files.h"
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
