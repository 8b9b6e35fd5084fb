#include "guarded_http_server.h"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

namespace fabkit::server {
namespace {

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

int millis_until(Clock::time_point t) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(t - Clock::now());
  return static_cast<int>(std::clamp<long long>(left.count(), 0, 1 << 30));
}

// Waits until `sock` can be read (or written); false at `until` or on error.
bool wait_for(int sock, short events, Clock::time_point until) {
  while (true) {
    pollfd p{sock, events, 0};
    const int n = ::poll(&p, 1, millis_until(until));
    if (n > 0) return (p.revents & (events | POLLHUP | POLLERR)) != 0;
    if (n == 0) return false;
    if (errno != EINTR) return false;
  }
}

void address_of(int sock, bool peer, std::string& ip, int& port) {
  sockaddr_storage addr{};
  socklen_t len = sizeof(addr);
  const int rc = peer ? ::getpeername(sock, reinterpret_cast<sockaddr*>(&addr), &len)
                      : ::getsockname(sock, reinterpret_cast<sockaddr*>(&addr), &len);
  if (rc != 0) return;
  char host[NI_MAXHOST];
  char serv[NI_MAXSERV];
  if (::getnameinfo(reinterpret_cast<sockaddr*>(&addr),
                    len,
                    host,
                    sizeof(host),
                    serv,
                    sizeof(serv),
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host;
    port = std::atoi(serv);
  }
}

// One client connection: its socket and the bytes read from it but not yet used, which belong
// to the next request when a client pipelines.
struct Connection {
  const std::atomic<socket_t>* server_socket = nullptr;
  int sock = -1;
  std::vector<char> buffer = std::vector<char>(16384);
  std::size_t begin = 0, end = 0;
  bool close_after = false;
};

thread_local Connection* t_connection = nullptr;

// The stream httplib parses one request from and writes its response to: reads stop at the
// request's deadline and byte budget, writes at the response's deadline.
class GuardedStream final : public httplib::Stream {
 public:
  GuardedStream(Connection& c, const ConnectionLimits& limits)
      : c_(c),
        limits_(limits),
        read_until_(Clock::now() + seconds(limits.request_read_s)),
        budget_(limits.max_request_bytes) {}

  bool is_readable() const override {
    return c_.begin < c_.end || wait_for(c_.sock, POLLIN, read_until_);
  }
  bool is_writable() const override { return wait_for(c_.sock, POLLOUT, write_until()); }

  ssize_t read(char* ptr, size_t size) override {
    if (size == 0) return 0;
    if (budget_ == 0) {
      c_.close_after = true;  // the rest of this request is never read: do not parse it
      return -1;
    }
    size = std::min(size, budget_);
    if (c_.begin == c_.end) {
      if (!wait_for(c_.sock, POLLIN, read_until_)) {
        c_.close_after = true;
        return -1;
      }
      ssize_t n;
      do {
        n = ::recv(c_.sock, c_.buffer.data(), c_.buffer.size(), 0);
      } while (n < 0 && errno == EINTR);
      if (n <= 0) {
        c_.close_after = true;
        return n;
      }
      c_.begin = 0;
      c_.end = static_cast<std::size_t>(n);
    }
    const std::size_t k = std::min(size, c_.end - c_.begin);
    std::memcpy(ptr, c_.buffer.data() + c_.begin, k);
    c_.begin += k;
    budget_ -= k;
    return static_cast<ssize_t>(k);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!wait_for(c_.sock, POLLOUT, write_until())) {
      c_.close_after = true;
      return -1;
    }
    ssize_t n;
    do {
      n = ::send(c_.sock, ptr, size, MSG_NOSIGNAL);
    } while (n < 0 && errno == EINTR);
    if (n < 0) c_.close_after = true;
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    address_of(c_.sock, true, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    address_of(c_.sock, false, ip, port);
  }
  socket_t socket() const override { return c_.sock; }

 private:
  // The response's clock starts with its first byte (the handler may take long before).
  Clock::time_point write_until() const {
    if (!write_started_) {
      write_started_ = Clock::now();
    }
    return *write_started_ + seconds(limits_.write_s);
  }

  Connection& c_;
  const ConnectionLimits& limits_;
  Clock::time_point read_until_;
  std::size_t budget_;
  mutable std::optional<Clock::time_point> write_started_;
};

// A request held in memory, for answer_raw().
class MemoryStream final : public httplib::Stream {
 public:
  MemoryStream(std::string_view in, std::string remote_ip, std::size_t budget)
      : in_(in), remote_(std::move(remote_ip)), budget_(budget) {}
  bool is_readable() const override { return true; }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const std::size_t k = std::min({size, in_.size() - at_, budget_});
    if (k == 0 && budget_ == 0 && at_ < in_.size()) return -1;
    std::memcpy(ptr, in_.data() + at_, k);
    at_ += k;
    budget_ -= k;
    return static_cast<ssize_t>(k);
  }
  ssize_t write(const char* ptr, size_t size) override {
    out_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    ip = remote_;
    port = 40000;
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    ip = "127.0.0.1";
    port = 8080;
  }
  socket_t socket() const override { return 0; }
  std::string& output() { return out_; }

 private:
  std::string_view in_;
  std::size_t at_ = 0;
  std::string remote_;
  std::size_t budget_;
  std::string out_;
};

void send_all(int sock, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::send(sock, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n <= 0) return;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

// A connection closed while its client still sends (a refused body) would be reset, and the
// client would not see the answer explaining why: read and drop what it sends for a moment.
void linger(int sock) {
  ::shutdown(sock, SHUT_WR);
  const Clock::time_point until = Clock::now() + std::chrono::seconds(2);
  std::size_t dropped = 0;
  char buffer[16384];
  while (dropped < (std::size_t{8} << 20) && wait_for(sock, POLLIN, until)) {
    const ssize_t n = ::recv(sock, buffer, sizeof(buffer), 0);
    if (n <= 0) break;
    dropped += static_cast<std::size_t>(n);
  }
}

}  // namespace

GuardedHttpServer::GuardedHttpServer(ConnectionLimits limits) : limits_(limits) {
  if (limits_.max_request_bytes == 0) limits_.max_request_bytes = std::size_t{1} << 20;
  // A worker per allowed connection and a few more, so refusing the excess is immediate.
  const std::size_t threads = static_cast<std::size_t>(std::max(1, limits_.max_open)) + 8;
  new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  set_keep_alive_max_count(static_cast<std::size_t>(std::max(1, limits_.keep_alive_requests)));
}

void GuardedHttpServer::widen_listen_backlog() {
  if (svr_sock_ != INVALID_SOCKET) ::listen(svr_sock_, std::max(128, limits_.max_open));
}

bool GuardedHttpServer::client_gone() {
  if (!t_connection || t_connection->sock < 0) return false;
  char c;
  const ssize_t n = ::recv(t_connection->sock, &c, 1, MSG_PEEK | MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
}

bool GuardedHttpServer::server_stopping() {
  return t_connection && t_connection->server_socket &&
         *t_connection->server_socket == INVALID_SOCKET;
}

void GuardedHttpServer::close_after_response() {
  if (t_connection) t_connection->close_after = true;
}

bool GuardedHttpServer::process_and_close_socket(socket_t sock) {
  struct Counted {
    std::atomic<int>& n;
    ~Counted() { --n; }
  } counted{open_};
  const int open = ++open_;
  if (open > limits_.max_open) {
    const std::string body = dump_json(Json{
        {"error",
         fmt::format("the server has {} connections open, its limit; try again", limits_.max_open)},
        {"diagnostics", Json::array()}});
    send_all(sock,
             fmt::format("HTTP/1.1 503 Service Unavailable\r\nContent-Type: application/json\r\n"
                         "Retry-After: 1\r\nConnection: close\r\nContent-Length: {}\r\n\r\n{}",
                         body.size(),
                         body));
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return false;
  }

  Connection connection;
  connection.sock = sock;
  connection.server_socket = &svr_sock_;
  t_connection = &connection;
  bool ok = false;
  for (int left = std::max(1, limits_.keep_alive_requests); left > 0; --left) {
    if (svr_sock_ == INVALID_SOCKET) break;  // the server is stopping
    if (connection.begin == connection.end &&
        !wait_for(sock, POLLIN, Clock::now() + seconds(limits_.keep_alive_s))) {
      break;
    }
    GuardedStream stream(connection, limits_);
    bool closed = false;
    ok = process_request(stream, left == 1, closed, nullptr);
    if (!ok || closed || connection.close_after) break;
  }
  t_connection = nullptr;
  if (connection.close_after) linger(sock);
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return ok;
}

std::string GuardedHttpServer::answer_raw(std::string_view request, const std::string& remote_ip) {
  MemoryStream stream(request, remote_ip, limits_.max_request_bytes);
  bool closed = false;
  process_request(stream, true, closed, nullptr);
  return std::move(stream.output());
}

}  // namespace fabkit::server
