// Validation of request bodies: every malformed or out-of-range value is a 400 naming the field.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "server/http_error.h"
#include "server/request_parsing.h"

namespace matlas::server {
namespace {

LatentDomain box() {
  Eigen::VectorXd lo(2), hi(2);
  lo << -1, 0;
  hi << 1, 2;
  return LatentDomain::around(lo, hi, 0.5);  // x in [-2, 2], y in [-1, 3]
}

int status_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const HttpError& e) {
    return e.status();
  }
  return 0;
}

TEST(LatentDomain, EnlargesTheDataBoxByTheMargin) {
  const LatentDomain d = box();
  EXPECT_DOUBLE_EQ(d.lo[0], -2.0);
  EXPECT_DOUBLE_EQ(d.hi[0], 2.0);
  EXPECT_DOUBLE_EQ(d.lo[1], -1.0);
  EXPECT_DOUBLE_EQ(d.hi[1], 3.0);
}

TEST(ParseLatent, AcceptsAPointInsideTheDomain) {
  const auto j = parse_json_object(R"({"x": [0.5, -0.25]})");
  const Eigen::VectorXd x = parse_latent(j, "x", box());
  EXPECT_DOUBLE_EQ(x[0], 0.5);
  EXPECT_DOUBLE_EQ(x[1], -0.25);
}

TEST(ParseLatent, RejectsWrongDimensionTypesNaNAndOutOfRange) {
  const LatentDomain d = box();
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": [0]})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": [0, 0, 0]})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": "0,0"})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": [0, "a"]})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"y": [0, 0]})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": [2.5, 0]})"), "x", d); }), 400);
  EXPECT_EQ(status_of([&] { parse_latent(parse_json_object(R"({"x": [0, -1.01]})"), "x", d); }), 400);
  nlohmann::json nan_body = {{"x", {0.0, std::numeric_limits<double>::quiet_NaN()}}};
  EXPECT_EQ(status_of([&] { parse_latent(nan_body, "x", d); }), 400);
  nlohmann::json inf_body = {{"x", {std::numeric_limits<double>::infinity(), 0.0}}};
  EXPECT_EQ(status_of([&] { parse_latent(inf_body, "x", d); }), 400);
}

TEST(ParseLatent, MessageNamesTheCoordinateAndTheRange) {
  try {
    parse_latent(parse_json_object(R"({"x": [0, 7]})"), "x", box());
    FAIL();
  } catch (const HttpError& e) {
    EXPECT_NE(std::string(e.what()).find("x[1] = 7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[-1, 3]"), std::string::npos) << e.what();
  }
}

TEST(ParseJsonObject, RejectsMalformedJsonAndNonObjects) {
  EXPECT_EQ(status_of([] { parse_json_object("{\"x\": [1, 2"); }), 400);
  EXPECT_EQ(status_of([] { parse_json_object(""); }), 400);
  EXPECT_EQ(status_of([] { parse_json_object("[1, 2]"); }), 400);
  EXPECT_EQ(status_of([] { parse_json_object("{\"x\": NaN}"); }), 400);
}

TEST(ParseFields, DefaultsRangesAndChoices) {
  const auto j = parse_json_object(R"({"n": 3.5, "k": 4, "s": "b", "f": 2.5})");
  EXPECT_DOUBLE_EQ(parse_number(j, "n", 0, 10, 1), 3.5);
  EXPECT_DOUBLE_EQ(parse_number(j, "missing", 0, 10, 1), 1.0);
  EXPECT_EQ(status_of([&] { parse_number(j, "n", 0, 3, 1); }), 400);
  EXPECT_EQ(parse_int(j, "k", 0, 10, 1), 4);
  EXPECT_EQ(status_of([&] { parse_int(j, "f", 0, 10, 1); }), 400);
  EXPECT_EQ(parse_choice(j, "s", {"a", "b"}, "a"), "b");
  EXPECT_EQ(status_of([&] { parse_choice(j, "s", {"a", "c"}, "a"); }), 400);
  EXPECT_EQ(parse_int_text("12", "size", 0, 20), 12);
  EXPECT_EQ(status_of([] { parse_int_text("12x", "size", 0, 20); }), 400);
  EXPECT_EQ(status_of([] { parse_int_text("99", "size", 0, 20); }), 400);
}

TEST(RequestParsing, NestingDepthIsCappedBeforeParsing) {
  EXPECT_EQ(json_nesting_depth("{\"x\":[[1],[2]]}", 100), 3u);
  EXPECT_EQ(json_nesting_depth("{\"s\":\"[[[[\\\"[[\"}", 100), 1u);  // brackets inside a string
  const std::string deep = "{\"top\":" + std::string(30000, '[') + std::string(30000, ']') + "}";
  EXPECT_EQ(status_of([&] { parse_json_object(deep); }), 400);
  const std::string deeper = "{\"top\":" + std::string(60000, '[') + std::string(60000, ']') + "}";
  EXPECT_EQ(status_of([&] { parse_json_object(deeper); }), 413);  // too large before too deep
  EXPECT_EQ(status_of([&] { parse_json_object(std::string(kMaxJsonBody + 1, ' ')); }), 413);
}

TEST(RequestParsing, IntegersAreComparedWithoutWrapping) {
  const auto body = nlohmann::json::parse(R"({"a": 4294967296, "b": 18446744073709551615, "c": -4294967296, "d": 7})");
  EXPECT_EQ(status_of([&] { parse_int(body, "a", 0, 100, 1); }), 400);
  EXPECT_EQ(status_of([&] { parse_int(body, "b", 0, 100, 1); }), 400);
  EXPECT_EQ(status_of([&] { parse_int(body, "c", 0, 100, 1); }), 400);
  EXPECT_EQ(parse_int(body, "d", 0, 100, 1), 7);
  try {
    parse_int(nlohmann::json::parse(R"({"t": [[[1]]]})"), "t", 0, 10, 1);
    FAIL();
  } catch (const HttpError& e) {
    EXPECT_STREQ(e.what(), "\"t\" must be an integer, got array");  // the type, never the value
  }
}

TEST(RequestParsing, AcceptEncodingWithoutACodingKeepsTheOthersAndTheirParameters) {
  EXPECT_EQ(accept_encoding_without("gzip, deflate, br", "br"), "gzip, deflate");
  EXPECT_EQ(accept_encoding_without("br;q=1.0, gzip;q=0.8", "br"), "gzip;q=0.8");
  EXPECT_EQ(accept_encoding_without("BR,gzip", "br"), "gzip");
  EXPECT_EQ(accept_encoding_without(" br ", "br"), "");
  EXPECT_EQ(accept_encoding_without("gzip, brotli-like, identity", "br"), "gzip, brotli-like, identity");
  EXPECT_EQ(accept_encoding_without("", "br"), "");
  EXPECT_EQ(accept_encoding_without(",,gzip,", "br"), "gzip");
}

}  // namespace
}  // namespace matlas::server
