// Listen address forms and loopback detection.
#include <gtest/gtest.h>

#include "server/config/daemon_config.h"

namespace omniview {
namespace {

TEST(ListenAddress, Loopback) {
  for (const char* a : {"127.0.0.1:1", "127.1.2.3:50051", "[::1]:5", "localhost:5", "LocalHost:5",
                        "[::ffff:127.0.0.1]:5", "unix:/tmp/x", "unix:///tmp/x", "unix-abstract:omniview"}) {
    EXPECT_TRUE(is_loopback_address(a)) << a;
  }
  for (const char* a : {"0.0.0.0:5", "[::]:5", "10.0.0.2:5", "192.168.1.7:50051", "robot.local:5",
                        "[fe80::1]:5", "128.0.0.1:5", ":5", "nonsense"}) {
    EXPECT_FALSE(is_loopback_address(a)) << a;
  }
}

TEST(ListenAddress, Forms) {
  for (const char* a : {"127.0.0.1:50051", "0.0.0.0:0", "[::]:65535", "localhost:1", "robot.local:50051",
                        "unix:/run/omniview.sock"}) {
    EXPECT_EQ(listen_address_problem(a), "") << a;
  }
  EXPECT_NE(listen_address_problem("").find("is empty"), std::string::npos);
  EXPECT_NE(listen_address_problem("unix:").find("no socket path"), std::string::npos);
  EXPECT_NE(listen_address_problem("127.0.0.1").find("not host:port"), std::string::npos);
  EXPECT_NE(listen_address_problem("::1:5").find("brackets"), std::string::npos);
  EXPECT_NE(listen_address_problem("[::1:5").find("not host:port"), std::string::npos);
  EXPECT_NE(listen_address_problem("[nothost]:5").find("not an IPv6 address"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:-1").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:65536").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem("a:123456").find("port must be"), std::string::npos);
  EXPECT_NE(listen_address_problem(":5").find("names no host"), std::string::npos);
}

}  // namespace
}  // namespace omniview
