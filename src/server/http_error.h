#pragma once
// HttpError: a request the server refuses, with the HTTP status to answer (4xx for the client's
// mistakes, 503 when the server is too busy) and a message for the user.
#include <string>

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

}  // namespace matlas::server
