// Who may talk to the server: Host and Origin checks against the bound address, and the body
// types a POST may have.
#include "request_policy.h"

#include <gtest/gtest.h>

namespace fabkit::server {
namespace {

TEST(RequestPolicy, HostMustNameTheLoopbackServerAndItsPort) {
  const HostPolicy p{"127.0.0.1", 8080, {}};
  EXPECT_FALSE(refuse_host(p, "127.0.0.1:8080"));
  EXPECT_FALSE(refuse_host(p, "localhost:8080"));
  EXPECT_FALSE(refuse_host(p, "LOCALHOST:8080"));
  EXPECT_FALSE(refuse_host(p, "[::1]:8080"));
  EXPECT_FALSE(refuse_host(p, " 127.0.0.1:8080 "));
  EXPECT_TRUE(refuse_host(p, "127.0.0.1"));  // port 80 implied
  EXPECT_TRUE(refuse_host(p, "127.0.0.1:8081"));
  EXPECT_TRUE(refuse_host(p, "127.0.0.1:"));
  EXPECT_TRUE(refuse_host(p, "127.0.0.1:08080x"));
  EXPECT_TRUE(refuse_host(p, "attacker.example:8080"));
  EXPECT_TRUE(refuse_host(p, "localhost.attacker.example:8080"));
  EXPECT_TRUE(refuse_host(p, "192.168.1.5:8080"));
  EXPECT_TRUE(refuse_host(p, ""));
  EXPECT_TRUE(refuse_host(p, "127.0.0.1:8080:8080"));
  EXPECT_TRUE(refuse_host(p, "[::1"));
  EXPECT_TRUE(refuse_host(p, "user@127.0.0.1:8080"));
  EXPECT_TRUE(refuse_host(p, std::string(100000, 'a')));
  const auto why = refuse_host(p, "attacker.example:8080");
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("127.0.0.1:8080"), std::string::npos) << *why;
  EXPECT_NE(why->find("--allow-host"), std::string::npos) << *why;
  EXPECT_LT(refuse_host(p, std::string(100000, 'a'))->size(), 400u);
}

TEST(RequestPolicy, AllInterfacesAnswerAddressesButNotNames) {
  const HostPolicy p{"0.0.0.0", 8080, {"workshop.lan"}};
  EXPECT_FALSE(refuse_host(p, "192.168.1.5:8080"));
  EXPECT_FALSE(refuse_host(p, "[fe80::1]:8080"));
  EXPECT_FALSE(refuse_host(p, "localhost:8080"));
  EXPECT_FALSE(refuse_host(p, "Workshop.LAN:8080"));
  EXPECT_TRUE(refuse_host(p, "attacker.example:8080"));
  const HostPolicy lan{"192.168.1.5", 80, {}};
  EXPECT_FALSE(refuse_host(lan, "192.168.1.5"));
  EXPECT_FALSE(refuse_host(lan, "192.168.1.5:80"));
  EXPECT_TRUE(refuse_host(lan, "localhost"));
  EXPECT_TRUE(refuse_host(lan, "127.0.0.1"));
}

TEST(RequestPolicy, OriginMustBeTheServerOrAbsent) {
  const HostPolicy p{"127.0.0.1", 8080, {}};
  EXPECT_FALSE(refuse_origin(p, ""));
  EXPECT_FALSE(refuse_origin(p, "http://127.0.0.1:8080"));
  EXPECT_FALSE(refuse_origin(p, "http://localhost:8080"));
  EXPECT_TRUE(refuse_origin(p, "null"));
  EXPECT_TRUE(refuse_origin(p, "https://127.0.0.1:8080"));
  EXPECT_TRUE(refuse_origin(p, "http://127.0.0.1:8080/path"));
  EXPECT_TRUE(refuse_origin(p, "http://attacker.example:8080"));
  EXPECT_TRUE(refuse_origin(p, "http://127.0.0.1:9999"));
}

TEST(RequestPolicy, BodiesMustBeYamlOrJson) {
  for (const char* ok : {"application/x-yaml",
                         "application/yaml",
                         "text/yaml",
                         "text/x-yaml",
                         "application/json",
                         "application/json; charset=utf-8",
                         "Application/JSON"}) {
    EXPECT_TRUE(is_design_media_type(ok)) << ok;
  }
  for (const char* bad : {"",
                          "text/plain",
                          "text/plain; charset=utf-8",
                          "application/x-www-form-urlencoded",
                          "multipart/form-data; boundary=a",
                          "application/jsonx",
                          "text/html"}) {
    EXPECT_FALSE(is_design_media_type(bad)) << bad;
  }
}

TEST(RequestPolicy, Loopback) {
  EXPECT_TRUE(is_loopback("127.0.0.1"));
  EXPECT_TRUE(is_loopback("127.1.2.3"));
  EXPECT_TRUE(is_loopback("::1"));
  EXPECT_TRUE(is_loopback("[::1]"));
  EXPECT_TRUE(is_loopback("localhost"));
  EXPECT_FALSE(is_loopback("0.0.0.0"));
  EXPECT_FALSE(is_loopback("127.example.com"));
  EXPECT_FALSE(is_loopback("192.168.0.1"));
}

}  // namespace
}  // namespace fabkit::server
