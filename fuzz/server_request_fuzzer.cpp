// Raw HTTP requests to the editor's server, as a web page or a local program could send them:
// request line, headers, bodies (chunked too), every route. No sockets: the server parses and
// answers the bytes in memory. Its answers must be HTTP and must never hold a file's contents.
#include <string>

#include "fabkit/server/editor_server.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  static server::EditorServer* const editor = [] {
    server::ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 8080;  // never bound: the Host a request must carry
    o.max_body_bytes = 64 << 10;
    o.max_parts = 20;
    o.max_connections = 40;
    o.solve_timeout_s = 0.05;
    o.job_workers = 1;
    o.initial_design = "fabkit: hacks/1\nenvironment: []\n";
    return new server::EditorServer(o);
  }();
  const std::string request(fuzz::text_of(data, size));
  const std::string answer = editor->answer_raw(request);
  if (!answer.empty()) {
    fuzz::require(answer.rfind("HTTP/1.1 ", 0) == 0, "an answer is not HTTP", answer);
  }
  // /etc/passwd's first line in an answer is a file read, unless the request itself carried
  // those bytes (a refused Host header is quoted back, truncated, in the error).
  fuzz::require(request.find("root:x:0:0") != std::string::npos ||
                    answer.find("root:x:0:0") == std::string::npos,
                "an answer holds /etc/passwd",
                answer);
  return 0;
}
