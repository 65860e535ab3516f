#include "server/guarded_http.h"

#include <arpa/inet.h>
#include <cerrno>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <functional>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace matlas::server {

namespace {

using Clock = std::chrono::steady_clock;

/// Milliseconds left until `deadline` (0 when past), capped for poll().
int millis_until(Clock::time_point deadline) {
  // Rounded up: a deadline 0.6 ms away must not read as "now".
  const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1 << 30));
}

void socket_address(const sockaddr_storage& addr, std::string& ip, int& port) {
  char text[INET6_ADDRSTRLEN] = {};
  if (addr.ss_family == AF_INET) {
    const auto* a = reinterpret_cast<const sockaddr_in*>(&addr);
    ::inet_ntop(AF_INET, &a->sin_addr, text, sizeof text);
    port = ntohs(a->sin_port);
  } else if (addr.ss_family == AF_INET6) {
    const auto* a = reinterpret_cast<const sockaddr_in6*>(&addr);
    ::inet_ntop(AF_INET6, &a->sin6_addr, text, sizeof text);
    port = ntohs(a->sin6_port);
  }
  ip = text;
}

/// A socket stream whose reads share one deadline and one byte budget (httplib's SocketStream
/// has a timeout per read and no budget).
class DeadlineStream final : public httplib::Stream {
public:
  DeadlineStream(socket_t sock, std::chrono::milliseconds write_timeout) : sock_(sock), write_timeout_(write_timeout) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    if (::getpeername(sock_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) socket_address(addr, remote_ip_, remote_port_);
    len = sizeof addr;
    if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&addr), &len) == 0) socket_address(addr, local_ip_, local_port_);
  }

  void limit(Clock::time_point deadline, std::size_t budget) {
    deadline_ = deadline;
    budget_ = budget;
  }
  bool timed_out() const { return timed_out_; }
  /// A read failed (deadline, budget, error or end of stream): the connection is not reusable
  /// (httplib may still have answered 400 on it).
  bool failed() const { return failed_ || over_budget_; }
  bool over_budget() const { return over_budget_; }
  bool close_requested() const { return close_requested_; }
  void request_close() { close_requested_ = true; }
  void reset_request_state() { close_requested_ = false; }
  const std::string& remote_ip() const { return remote_ip_; }

  bool is_readable() const override { return wait(POLLIN, millis_until(deadline_)); }
  bool is_writable() const override { return wait(POLLOUT, static_cast<int>(write_timeout_.count())); }

  /// Bytes received but not yet read (httplib reads headers a byte at a time: they come from
  /// this buffer, not one system call each).
  bool has_buffered() const { return buffer_begin_ < buffer_end_; }

  ssize_t read(char* ptr, size_t size) override {
    if (budget_ == 0) {
      over_budget_ = true;
      return -1;
    }
    size = std::min(size, budget_);
    if (!has_buffered()) {
      for (;;) {
        if (!wait(POLLIN, millis_until(deadline_))) {
          if (Clock::now() < deadline_ && !hung_up()) continue;  // woke early
          timed_out_ = Clock::now() >= deadline_;
          failed_ = true;
          return -1;
        }
        // Large reads go straight to the caller; small ones fill the buffer.
        if (size >= sizeof buffer_) {
          const ssize_t n = ::recv(sock_, ptr, size, 0);
          if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
          if (n > 0) budget_ -= static_cast<std::size_t>(n);
          else failed_ = true;
          return n;
        }
        const ssize_t n = ::recv(sock_, buffer_, sizeof buffer_, 0);
        if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (n <= 0) {
          failed_ = true;
          return n;
        }
        buffer_begin_ = 0;
        buffer_end_ = static_cast<std::size_t>(n);
        break;
      }
    }
    const std::size_t n = std::min(size, buffer_end_ - buffer_begin_);
    std::memcpy(ptr, buffer_ + buffer_begin_, n);
    buffer_begin_ += n;
    budget_ -= n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, size_t size) override {
    for (;;) {
      if (!is_writable()) return -1;
      const ssize_t n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      return n;
    }
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = remote_ip_;
    port = remote_port_;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = local_ip_;
    port = local_port_;
  }
  socket_t socket() const override { return sock_; }

private:
  bool hung_up() const {
    pollfd p{sock_, POLLIN, 0};
    return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0;
  }
  bool wait(short events, int millis) const {
    pollfd p{sock_, events, 0};
    for (;;) {
      const int r = ::poll(&p, 1, millis);
      if (r < 0 && errno == EINTR) continue;
      return r > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
    }
  }

  socket_t sock_;
  std::chrono::milliseconds write_timeout_;
  Clock::time_point deadline_ = Clock::now();
  std::size_t budget_ = 0;
  bool timed_out_ = false, over_budget_ = false, close_requested_ = false, failed_ = false;
  char buffer_[4096];
  std::size_t buffer_begin_ = 0, buffer_end_ = 0;
  std::string remote_ip_, local_ip_;
  int remote_port_ = -1, local_port_ = -1;
};

thread_local DeadlineStream* t_stream = nullptr;  ///< the connection this worker serves

std::chrono::milliseconds& t_body_timeout() {
  thread_local std::chrono::milliseconds timeout{60000};
  return timeout;
}
thread_local bool t_refuse = false;               ///< set while a full pool refuses a connection

/// Closes after the reply: first our side only, then reads and discards what the client may still
/// be sending (an unread body refused with 413) for a short while, so that the client reads the
/// reply instead of a connection reset; then the socket.
void lingering_close(socket_t sock) {
  ::shutdown(sock, SHUT_WR);
  const auto deadline = Clock::now() + std::chrono::milliseconds(500);
  std::size_t budget = 16u << 20;
  char buf[16384];
  while (budget > 0) {
    pollfd p{sock, POLLIN, 0};
    if (::poll(&p, 1, millis_until(deadline)) <= 0) break;
    const ssize_t n = ::recv(sock, buf, sizeof buf, MSG_DONTWAIT);
    if (n <= 0) break;
    budget -= std::min(budget, static_cast<std::size_t>(n));
  }
  ::close(sock);
}

/// A short reply on a connection that is not served (no request read): best effort, never blocks
/// on the client. On a worker thread (`linger`), what the client sends meanwhile is drained
/// briefly so that it reads the reply; on the accepting thread the socket is closed at once.
void refuse(socket_t sock, const std::string& message, bool linger) {
  const std::string body = "{\"error\": \"" + message + "\"}";
  const std::string reply = "HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
                            "Retry-After: 1\r\nConnection: close\r\nContent-Length: " +
                            std::to_string(body.size()) + "\r\n\r\n" + body;
  [[maybe_unused]] const ssize_t sent = ::send(sock, reply.data(), reply.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  if (linger) {
    lingering_close(sock);
    return;
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
}

}  // namespace

/// httplib's task queue with a bound: `threads` workers, at most `queue` waiting connections;
/// beyond, the connection is refused at once on the accepting thread (the task runs with
/// t_refuse set, and process_and_close_socket answers 503 without reading).
class BoundedPool final : public httplib::TaskQueue {
public:
  BoundedPool(int threads, int queue) : max_queue_(static_cast<std::size_t>(std::max(0, queue))) {
    for (int i = 0; i < std::max(1, threads); ++i) workers_.emplace_back([this] { work(); });
  }
  ~BoundedPool() override = default;

  void enqueue(std::function<void()> fn) override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (jobs_.size() < max_queue_ || idle_ > jobs_.size()) {
        jobs_.push_back(std::move(fn));
        cond_.notify_one();
        return;
      }
    }
    t_refuse = true;
    fn();
    t_refuse = false;
  }

  void shutdown() override {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      shutdown_ = true;
    }
    cond_.notify_all();
    for (auto& t : workers_) t.join();
  }

private:
  void work() {
    for (;;) {
      std::function<void()> fn;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ++idle_;
        cond_.wait(lock, [&] { return !jobs_.empty() || shutdown_; });
        --idle_;
        if (shutdown_ && jobs_.empty()) return;
        fn = std::move(jobs_.front());
        jobs_.pop_front();
      }
      fn();
    }
  }

  std::size_t max_queue_;
  std::size_t idle_ = 0;
  bool shutdown_ = false;
  std::deque<std::function<void()>> jobs_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable cond_;
};

GuardedHttpServer::GuardedHttpServer(ConnectionLimits limits) : limits_(limits) {
  new_task_queue = [this] { return new BoundedPool(limits_.threads, limits_.queue); };
  set_read_timeout(std::chrono::duration_cast<std::chrono::seconds>(limits_.header_timeout).count() + 1);
  set_write_timeout(std::chrono::duration_cast<std::chrono::seconds>(limits_.write_timeout).count() + 1);
  set_keep_alive_timeout(std::chrono::duration_cast<std::chrono::seconds>(limits_.idle_timeout).count() + 1);
}

void GuardedHttpServer::begin_body(std::size_t max_bytes) {
  if (!t_stream) return;
  // Chunked transfer adds a size line per chunk: allow an eighth more, and 16 KiB of slack.
  t_stream->limit(Clock::now() + t_body_timeout(), max_bytes + max_bytes / 8 + (16u << 10));
}

void GuardedHttpServer::close_after_response() {
  if (t_stream) t_stream->request_close();
}

bool GuardedHttpServer::discard_body(std::size_t bytes) {
  if (!t_stream) return false;
  char buf[16384];
  while (bytes > 0) {
    const ssize_t n = t_stream->read(buf, std::min(bytes, sizeof buf));
    if (n <= 0) return false;
    bytes -= static_cast<std::size_t>(n);
  }
  return true;
}

ConnectionStats GuardedHttpServer::stats() const {
  return {accepted_.load(), refused_busy_.load(), refused_per_client_.load(), timed_out_.load(), over_budget_.load()};
}

bool GuardedHttpServer::wait_for_request(socket_t sock) const {
  const auto deadline = Clock::now() + limits_.idle_timeout;
  // In slices, so that stop() does not wait for idle connections.
  while (!stopping()) {
    const int left = millis_until(deadline);
    if (left == 0) return false;
    pollfd p{sock, POLLIN, 0};
    const int r = ::poll(&p, 1, std::min(left, 200));
    if (r < 0 && errno != EINTR) return false;
    if (r > 0) {
      if (p.revents & (POLLERR | POLLNVAL)) return false;
      char byte;
      // Readable: a request's first byte, or the client closed (recv 0).
      const ssize_t n = ::recv(sock, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
      return n > 0;
    }
  }
  return false;
}

bool GuardedHttpServer::process_and_close_socket(socket_t sock) {
  if (t_refuse) {
    ++refused_busy_;
    refuse(sock, "the server is busy; try again", false);
    return false;
  }
  // httplib sets this in the connection loop replaced here: headers and body go out in separate
  // writes, and without it Nagle + delayed ACK hold the second one for up to 40 ms.
  const int one = 1;
  ::setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  DeadlineStream stream(sock, limits_.write_timeout);
  const std::string client = stream.remote_ip();
  bool admitted = false;
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    int& open = clients_[client];
    if (open < limits_.per_client) {
      ++open;
      admitted = true;
    }
  }
  if (!admitted) {
    ++refused_per_client_;
    refuse(sock, "too many connections from " + client, true);
    return false;
  }
  ++accepted_;
  t_stream = &stream;
  t_body_timeout() = limits_.body_timeout;
  // As httplib's own loop: up to 1000 requests per connection, the last one told to close.
  for (int count = 0; count < 1000; ++count) {
    if (!stream.has_buffered() && !wait_for_request(sock)) break;
    stream.limit(Clock::now() + limits_.header_timeout, limits_.max_header_bytes);
    stream.reset_request_state();
    bool closed = false;
    const bool ok = process_request(stream, count == 999 || stopping(), closed, nullptr);
    if (after_request) after_request();
    if (stream.timed_out()) ++timed_out_;
    if (stream.over_budget()) ++over_budget_;
    if (!ok || closed || stream.close_requested() || stream.failed()) break;
  }
  t_stream = nullptr;
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    if (--clients_[client] <= 0) clients_.erase(client);
  }
  lingering_close(sock);
  return true;
}

}  // namespace matlas::server
