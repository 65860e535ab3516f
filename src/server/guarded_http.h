#pragma once
// GuardedHttpServer: cpp-httplib's server with the connection handling replaced, so that slow,
// idle or greedy clients cannot take the server from the others.
//
// httplib serves each connection on one worker thread for its whole life. Its own loop waits
// `read_timeout` per read, so a client trickling one byte before each timeout holds a worker
// forever, and idle keep-alive connections hold workers until they time out. Here:
//  - a bounded pool: `threads` workers and a queue of at most `queue` accepted connections; a
//    connection beyond that is answered 503 at once and closed;
//  - at most `per_client` simultaneous connections per client address (503 beyond);
//  - deadlines for a whole request, not per read: the request line and headers must arrive within
//    `header_timeout` of their first byte, the body within `body_timeout` of the headers, and
//    an idle connection is closed after `idle_timeout` without a new request;
//  - byte budgets: 64 KiB of headers, and the body limit the pre-routing handler sets for the
//    endpoint (begin_body), enforced while reading, chunked bodies included.
// Everything else (parsing, routing, handlers, responses) is httplib's, through its protected
// process_request.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>

// Last among the includes of files that include this header: see atlas_server.cpp.
#include <httplib.h>

namespace matlas::server {

struct ConnectionLimits {
  int threads = 256;                                  ///< worker threads, one connection each
  int queue = 512;                                    ///< accepted connections waiting for a worker
  int per_client = 64;                                ///< simultaneous connections per client address
  std::chrono::milliseconds idle_timeout{5000};       ///< wait for the next request on a connection
  std::chrono::milliseconds header_timeout{5000};     ///< request line and headers, from the first byte
  std::chrono::milliseconds body_timeout{60000};      ///< the body, from the end of the headers
  std::chrono::milliseconds write_timeout{10000};     ///< each write of the response
  std::size_t max_header_bytes = 64u << 10;           ///< request line and headers
};

struct ConnectionStats {
  std::uint64_t accepted = 0;            ///< connections served (admitted)
  std::uint64_t refused_busy = 0;        ///< 503: the queue was full
  std::uint64_t refused_per_client = 0;  ///< 503: too many connections from one address
  std::uint64_t timed_out = 0;           ///< closed by a header/body deadline
  std::uint64_t over_budget = 0;         ///< closed for sending more bytes than allowed
};

class GuardedHttpServer : public httplib::Server {
public:
  explicit GuardedHttpServer(ConnectionLimits limits);

  /// From the pre-routing handler (the request's headers are read, its body not yet): allows
  /// `max_bytes` of body (plus chunked-encoding overhead), to arrive within the body timeout.
  static void begin_body(std::size_t max_bytes);
  /// From a handler: close the connection after this response (e.g. the body was not read).
  static void close_after_response();
  /// From the pre-routing handler: reads and discards up to `max_bytes` of the body, so that the
  /// client receives the error reply instead of a connection reset. False if it could not.
  static bool discard_body(std::size_t bytes);

  ConnectionStats stats() const;
  /// Called on the worker thread after each request of a connection (its response written).
  std::function<void()> after_request;
  const ConnectionLimits& limits() const { return limits_; }

private:
  bool process_and_close_socket(socket_t sock) override;
  bool stopping() const { return svr_sock_ == INVALID_SOCKET; }
  /// Waits up to idle_timeout for the next request's first byte (false: closed, idle, stopping).
  bool wait_for_request(socket_t sock) const;

  ConnectionLimits limits_;
  std::mutex clients_mutex_;
  std::map<std::string, int> clients_;  ///< open connections per client address
  std::atomic<std::uint64_t> accepted_{0}, refused_busy_{0}, refused_per_client_{0}, timed_out_{0},
      over_budget_{0};
  friend class BoundedPool;
};

}  // namespace matlas::server
