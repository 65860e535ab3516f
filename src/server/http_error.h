#pragma once
// HttpError: a request the server refuses, with the HTTP status to answer (4xx for the client's
// mistakes, 503 when the server is too busy) and a message for the user.
#include <cstddef>
#include <string>
#include <string_view>

#include "core/error.h"

namespace matlas::server {

class HttpError : public Error {
public:
  HttpError(int status, const std::string& message) : Error(message), status_(status) {}
  int status() const { return status_; }

private:
  int status_;
};

/// 400 Bad Request with `message`.
inline HttpError bad_request(const std::string& message) { return HttpError(400, message); }

/// A value from a request made safe to quote in an error message: double-quoted, printable ASCII
/// kept, every other byte (control characters, invalid or valid UTF-8 alike) written as \xNN, and
/// cut after `max_bytes` of the value with the total length given ("\"abc...\" (5000 bytes)").
/// The JSON reply then never meets invalid UTF-8, and a long value is never echoed whole.
std::string quoted_excerpt(std::string_view value, std::size_t max_bytes = 40);

}  // namespace matlas::server
