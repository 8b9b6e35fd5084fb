#pragma once
// Who may talk to the server, decided from a request's headers before anything else is read:
// a web page the user visits can make the browser send requests to 127.0.0.1, so the server
// answers only requests addressed to it by its own name (the Host header: DNS rebinding gives
// an attacker's name), and POSTs only with a YAML or JSON body type and an own or no Origin
// (a cross-site form or "simple" fetch cannot set those without a CORS preflight, which the
// server never grants). Pure functions, tested and fuzzed on their own.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fabkit::server {

struct HostPolicy {
  std::string bound_host;                ///< the address listened on ("127.0.0.1", "0.0.0.0")
  int port = 0;                          ///< the port listened on
  std::vector<std::string> extra_names;  ///< more names this server answers to ("myhost.lan")
};

/// Why a request with this Host header (host[:port]) is not for this server, or nullopt when it
/// is: the bound address (any address of the machine when bound to all), "localhost" when
/// bound to loopback, or one of `extra_names`, with the bound port.
std::optional<std::string> refuse_host(const HostPolicy& policy, std::string_view host_header);

/// Why a request with this Origin header is refused, or nullopt: absent, or
/// http://<an allowed host>[:port].
std::optional<std::string> refuse_origin(const HostPolicy& policy, std::string_view origin);

/// Whether a POST body of this Content-Type may be read: YAML (application/yaml,
/// application/x-yaml, text/yaml, text/x-yaml) or JSON (application/json), with parameters.
bool is_design_media_type(std::string_view content_type);

/// Whether `host` is a loopback address or name (127.0.0.0/8, ::1, localhost).
bool is_loopback(std::string_view host);

}  // namespace fabkit::server
