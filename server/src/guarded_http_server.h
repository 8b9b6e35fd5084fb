#pragma once
// cpp-httplib's server with the connection handling a local server needs against slow and
// hostile clients, which httplib 0.11 does not offer as options: a request must arrive whole
// within a time limit (its read timeout applies to each recv, so a client trickling a byte
// every few seconds held a worker thread forever), at most so many bytes per request (its
// header lines and chunked bodies are otherwise unbounded), at most so many open connections
// (beyond it: an immediate 503), and keep-alive connections that keep pipelined bytes.
// Everything else — parsing, routing, handlers, responses — is httplib's own.

// clang-format off
#include "fabkit/core/json.h"
#include <httplib.h>
// clang-format on

#include <atomic>
#include <chrono>
#include <cstddef>
#include <string>
#include <string_view>

namespace fabkit::server {

struct ConnectionLimits {
  int max_open = 96;                  ///< connections served at once; more get 503
  double request_read_s = 10;         ///< a request (line, headers, body) must arrive within this
  double write_s = 30;                ///< a response must be taken by the client within this
  double keep_alive_s = 5;            ///< an idle keep-alive connection is closed after this
  int keep_alive_requests = 100;      ///< requests per connection
  std::size_t max_request_bytes = 0;  ///< line + headers + body, as read from the socket
};

class GuardedHttpServer : public httplib::Server {
 public:
  explicit GuardedHttpServer(ConnectionLimits limits);

  /// Answers one raw HTTP request as if it came over a connection from `remote_ip` (for tests
  /// and fuzzing: no sockets); returns the raw response bytes.
  std::string answer_raw(std::string_view request, const std::string& remote_ip = "127.0.0.1");

  /// After binding: a listen backlog as long as the connection limit (httplib's is 5, so a burst
  /// of clients had connections dropped and retried after a second).
  void widen_listen_backlog();

  /// Connections open now.
  int open_connections() const { return open_.load(); }

  /// From a handler: whether the client of the request being answered on this thread has
  /// closed its connection (nothing to answer any more). False outside a connection.
  static bool client_gone();
  /// From a handler: close the connection after this response (its body was not read whole).
  static void close_after_response();
  /// From a handler: whether the server answering on this thread is stopping.
  static bool server_stopping();

 private:
  bool process_and_close_socket(socket_t sock) override;

  ConnectionLimits limits_;
  std::atomic<int> open_{0};
};

}  // namespace fabkit::server
