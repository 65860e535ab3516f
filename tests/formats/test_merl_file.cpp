#include <cmath>
#include <cstring>
#include <cstdint>
#include <fstream>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.h"
#include "formats/merl_file.h"
#include "support/error_of.h"
#include "support/temp_dir.h"

namespace matlas {
namespace {

BrdfTable pattern_table(MerlDims dims = {}) {
  BrdfTable t(dims);
  for (std::size_t i = 0; i < t.size(); ++i) t.stored()[i] = std::sin(0.001 * i) * 1e3 + 0.1 / (1 + i);
  t.set_missing(0, 5);
  return t;
}

void write_raw(const std::filesystem::path& p, const std::int32_t dims[3], std::size_t values,
               double fill = 1.0) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(dims), 12);
  for (std::size_t i = 0; i < values; ++i) out.write(reinterpret_cast<const char*>(&fill), 8);
}

std::string error_of(const std::filesystem::path& p) {
  try {
    read_merl(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(MerlFile, RoundTripIsBitExact) {
  test::TempDir dir;
  const BrdfTable t = pattern_table();
  write_merl(dir / "a.binary", t);
  EXPECT_EQ(std::filesystem::file_size(dir / "a.binary"), 34992012u);
  const BrdfTable r = read_merl(dir / "a.binary");
  ASSERT_EQ(r.dims(), t.dims());
  EXPECT_EQ(0, std::memcmp(r.stored().data(), t.stored().data(), t.size() * 8));
  EXPECT_FALSE(r.measured(0, 5));
  // And again: file -> table -> file gives the same bytes.
  write_merl(dir / "b.binary", r);
  std::ifstream a(dir / "a.binary", std::ios::binary), b(dir / "b.binary", std::ios::binary);
  EXPECT_TRUE(std::equal(std::istreambuf_iterator<char>(a), {}, std::istreambuf_iterator<char>(b)));
}

TEST(MerlFile, PhysicalValuesUseTheReferenceScales) {
  test::TempDir dir;
  BrdfTable t(MerlDims{2, 2, 2});
  t.stored()[0] = 1500.0;
  t.stored()[8] = 1500.0;
  t.stored()[16] = 1500.0;
  write_merl(dir / "s.binary", t, /*allow_nonstandard_dims=*/true);
  const BrdfTable r = read_merl(dir / "s.binary");
  EXPECT_DOUBLE_EQ(r.value(0, 0), 1500.0 * (1.0 / 1500.0));
  EXPECT_DOUBLE_EQ(r.value(1, 0), 1500.0 * (1.15 / 1500.0));
  EXPECT_DOUBLE_EQ(r.value(2, 0), 1500.0 * (1.66 / 1500.0));
}

TEST(MerlFile, NonStandardDimsAreReadButNotWrittenForOtherTools) {
  test::TempDir dir;
  BrdfTable t(MerlDims{4, 5, 6});
  EXPECT_THROW(write_merl(dir / "x.binary", t), Error);
  EXPECT_FALSE(std::filesystem::exists(dir / "x.binary"));
  write_merl(dir / "x.binary", t, true);
  EXPECT_EQ(read_merl(dir / "x.binary").dims(), (MerlDims{4, 5, 6}));
}

TEST(MerlFile, TablesTheReaderRefusesAreNotWritten) {
  // write_merl used to write whatever it was given: a file that read_merl then refused.
  test::TempDir dir;
  for (const double bad : {1e300, -3e38, std::numeric_limits<double>::infinity(), std::nan("")}) {
    BrdfTable t = pattern_table();
    t.stored()[t.dims().bins() + 7] = bad;  // green, bin 7
    const std::string e = test::error_of([&] { write_merl(dir / "x.binary", t); });
    EXPECT_EQ(e.rfind((dir / "x.binary").string() + ": refusing to write value ", 0), 0u) << e;
    EXPECT_NE(e.find("in the green channel at bin 7"), std::string::npos) << e;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.binary"));
  }
  BrdfTable t = pattern_table();
  t.stored()[3] = 0.99e15;  // the largest values readers accept are written
  write_merl(dir / "x.binary", t);
  EXPECT_EQ(read_merl(dir / "x.binary").stored()[3], 0.99e15);
}

TEST(MerlFile, BadFilesGiveClearErrorsNamingTheFile) {
  test::TempDir dir;
  const auto p = dir / "bad.binary";
  EXPECT_NE(error_of(dir / "missing.binary").find("missing.binary: no such file"), std::string::npos);
  EXPECT_NE(error_of(dir.path()).find("is a directory"), std::string::npos);
  { std::ofstream(p, std::ios::binary); }
  EXPECT_NE(error_of(p).find("bad.binary: empty file"), std::string::npos);
  { std::ofstream(p, std::ios::binary) << "abc"; }
  EXPECT_NE(error_of(p).find("shorter than the 12-byte MERL header"), std::string::npos);
  const std::int32_t good[3] = {2, 2, 2};
  write_raw(p, good, 23);
  EXPECT_NE(error_of(p).find("truncated"), std::string::npos);
  write_raw(p, good, 25);
  EXPECT_NE(error_of(p).find("size mismatch"), std::string::npos);
  const std::int32_t negative[3] = {90, -90, 180};
  write_raw(p, negative, 1);
  EXPECT_NE(error_of(p).find("invalid MERL header"), std::string::npos);
  const std::int32_t absurd[3] = {90, 90, 1000000};
  write_raw(p, absurd, 1);
  EXPECT_NE(error_of(p).find("invalid MERL header"), std::string::npos);
  write_raw(p, good, 24, std::numeric_limits<double>::quiet_NaN());
  EXPECT_NE(error_of(p).find("NaN value in the red channel at bin 0"), std::string::npos);
  write_raw(p, good, 24, std::numeric_limits<double>::infinity());
  EXPECT_NE(error_of(p).find("infinite value"), std::string::npos);
}

TEST(MerlFile, PartialReadsMatchWholeRead) {
  test::TempDir dir;
  const BrdfTable t = pattern_table();
  write_merl(dir / "a.binary", t);
  MerlFile f(dir / "a.binary");
  std::vector<double> block(1000);
  f.read_values(2000000, block.size(), block.data());
  for (std::size_t i = 0; i < block.size(); ++i) EXPECT_EQ(block[i], t.stored()[2000000 + i]);
}

std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::string raw_bytes(const std::int32_t dims[3], std::size_t values, double fill = 1.0) {
  std::string bytes(reinterpret_cast<const char*>(dims), 12);
  for (std::size_t i = 0; i < values; ++i) bytes.append(reinterpret_cast<const char*>(&fill), 8);
  return bytes;
}

TEST(MerlBytes, EncodeIsTheFileWriteMerlWritesAndDecodeReadsItBack) {
  test::TempDir dir;
  const BrdfTable t = pattern_table();
  write_merl(dir / "a.binary", t);
  const std::string bytes = encode_merl(t);
  ASSERT_EQ(bytes.size(), 34992012u);
  EXPECT_TRUE(bytes == file_bytes(dir / "a.binary"));
  // decode(file's bytes) is bit-exact against read_merl of the file, missing values included.
  const BrdfTable from_file = read_merl(dir / "a.binary");
  const BrdfTable decoded = decode_merl(file_bytes(dir / "a.binary"), "upload");
  ASSERT_EQ(decoded.dims(), from_file.dims());
  EXPECT_EQ(0, std::memcmp(decoded.stored().data(), from_file.stored().data(), t.size() * 8));
  EXPECT_FALSE(decoded.measured(0, 5));
  // Non-standard dims go through memory as well (write_merl's refusal is for files).
  BrdfTable small(MerlDims{2, 3, 4});
  for (std::size_t i = 0; i < small.size(); ++i) small.stored()[i] = -0.5 + 0.25 * static_cast<double>(i);
  const BrdfTable back = decode_merl(encode_merl(small), "small");
  ASSERT_EQ(back.dims(), small.dims());
  EXPECT_EQ(0, std::memcmp(back.stored().data(), small.stored().data(), small.size() * 8));
}

TEST(MerlBytes, MalformedBytesGiveTheErrorsOfAFileNamingTheSource) {
  auto error = [](const std::string& bytes) { return test::error_of([&] { decode_merl(bytes, "upload"); }); };
  EXPECT_EQ(error(""), "upload: empty file, expected a MERL .binary BRDF");
  EXPECT_NE(error("abc").find("upload: truncated: 3 bytes, shorter than the 12-byte MERL header"), std::string::npos);
  const std::int32_t good[3] = {2, 2, 2};
  EXPECT_NE(error(raw_bytes(good, 23)).find("upload: truncated: 196 bytes, but header"), std::string::npos);
  EXPECT_NE(error(raw_bytes(good, 25)).find("upload: size mismatch: 212 bytes"), std::string::npos);
  const std::int32_t negative[3] = {90, -90, 180}, absurd[3] = {90, 90, 1000000};
  EXPECT_NE(error(raw_bytes(negative, 1)).find("upload: invalid MERL header: dims 90 -90 180"), std::string::npos);
  EXPECT_NE(error(raw_bytes(absurd, 1)).find("upload: invalid MERL header"), std::string::npos);
  EXPECT_EQ(error(raw_bytes(good, 24, std::numeric_limits<double>::quiet_NaN())),
            "upload: NaN value in the red channel at bin 0");
  std::string one_bad = raw_bytes(good, 24);
  const double inf = -std::numeric_limits<double>::infinity();
  std::memcpy(one_bad.data() + 12 + 8 * 9, &inf, 8);  // value 9: green channel (8 bins), bin 1
  EXPECT_EQ(error(one_bad), "upload: infinite value in the green channel at bin 1");
  EXPECT_NE(error(raw_bytes(good, 24, 1e16)).find("upload: absurd value 1e+16 in the red channel"), std::string::npos);
  EXPECT_EQ(error(raw_bytes(good, 24, -1.0)), "no error");  // negative values mean "missing"
}

}  // namespace
}  // namespace matlas
