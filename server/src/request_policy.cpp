#include "request_policy.h"

#include <arpa/inet.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "fabkit/core/text.h"

namespace fabkit::server {
namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

bool is_ipv4(const std::string& s) {
  in_addr a{};
  return ::inet_pton(AF_INET, s.c_str(), &a) == 1;
}

bool is_ipv6(const std::string& s) {
  in6_addr a{};
  return ::inet_pton(AF_INET6, s.c_str(), &a) == 1;
}

bool is_wildcard(const std::string& host) {
  return host.empty() || host == "0.0.0.0" || host == "::" || host == "[::]";
}

// "[::1]" → "::1"; lower case.
std::string normalized(std::string_view host) {
  std::string h = ascii_lower(trim(host));
  if (h.size() >= 2 && h.front() == '[' && h.back() == ']') h = h.substr(1, h.size() - 2);
  return h;
}

struct Authority {
  std::string host;  // normalized, IPv6 without brackets
  std::optional<int> port;
};

std::optional<Authority> parse_authority(std::string_view text) {
  text = trim(text);
  if (text.empty() || text.size() > 300) return std::nullopt;
  Authority a;
  std::string_view port;
  bool has_port = false;
  if (text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string_view::npos) return std::nullopt;
    a.host = ascii_lower(text.substr(1, close - 1));
    if (!is_ipv6(a.host)) return std::nullopt;
    const std::string_view rest = text.substr(close + 1);
    if (!rest.empty()) {
      if (rest.front() != ':') return std::nullopt;
      port = rest.substr(1);
      has_port = true;
    }
  } else {
    const auto colon = text.find(':');
    if (colon != std::string_view::npos) {
      if (text.find(':', colon + 1) != std::string_view::npos) return std::nullopt;
      port = text.substr(colon + 1);
      text = text.substr(0, colon);
      has_port = true;
    }
    a.host = ascii_lower(text);
    for (char c : a.host) {
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_')) {
        return std::nullopt;
      }
    }
    if (a.host.empty()) return std::nullopt;
  }
  if (has_port) {
    if (port.empty() || port.size() > 5) return std::nullopt;
    int p = 0;
    for (char c : port) {
      if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
      p = p * 10 + (c - '0');
    }
    if (p <= 0 || p > 65535) return std::nullopt;
    a.port = p;
  }
  return a;
}

bool host_allowed(const HostPolicy& policy, const std::string& host) {
  const std::string bound = normalized(policy.bound_host);
  if (host == bound) return true;
  for (const std::string& name : policy.extra_names) {
    if (host == normalized(name)) return true;
  }
  if (is_wildcard(bound)) return host == "localhost" || is_ipv4(host) || is_ipv6(host);
  if (is_loopback(bound)) return is_loopback(host);
  return false;
}

std::string bound_authority(const HostPolicy& policy) {
  const std::string h = normalized(policy.bound_host);
  return fmt::format("{}:{}", h.find(':') != std::string::npos ? "[" + h + "]" : h, policy.port);
}

}  // namespace

bool is_loopback(std::string_view host_text) {
  const std::string host = normalized(host_text);
  if (host == "localhost" || host == "::1") return true;
  return is_ipv4(host) && host.rfind("127.", 0) == 0;
}

std::optional<std::string> refuse_host(const HostPolicy& policy, std::string_view host_header) {
  const auto a = parse_authority(host_header);
  if (!a) {
    return host_header.empty()
               ? std::string(
                     "the request has no Host header; this server answers only requests "
                     "addressed to it")
               : fmt::format("the Host header '{}' is not a host name or address",
                             excerpt(host_header, 80));
  }
  const bool port_ok = a->port ? *a->port == policy.port : policy.port == 80;
  if (!port_ok || !host_allowed(policy, a->host)) {
    return fmt::format(
        "the request is addressed to '{}', not to this server ({}); a server reached under "
        "another name must be started with --allow-host NAME",
        excerpt(host_header, 80),
        bound_authority(policy));
  }
  return std::nullopt;
}

std::optional<std::string> refuse_origin(const HostPolicy& policy, std::string_view origin) {
  origin = trim(origin);
  if (origin.empty()) return std::nullopt;
  constexpr std::string_view kScheme = "http://";
  if (ascii_lower(origin.substr(0, kScheme.size())) == kScheme) {
    const std::string_view authority = origin.substr(kScheme.size());
    if (authority.find('/') == std::string_view::npos && !refuse_host(policy, authority)) {
      return std::nullopt;
    }
  }
  return fmt::format(
      "requests from the page at '{}' are refused: only the editor this server serves may "
      "send designs to it",
      excerpt(origin, 80));
}

bool is_design_media_type(std::string_view content_type) {
  const std::string type = ascii_lower(trim(content_type.substr(0, content_type.find(';'))));
  return type == "application/yaml" || type == "application/x-yaml" || type == "text/yaml" ||
         type == "text/x-yaml" || type == "application/json";
}

}  // namespace fabkit::server
