// Refused calls are logged at a bounded rate per peer host, and the next line written
// says how many were left out.
#include <gtest/gtest.h>

#include "server/auth/refusal_log.h"

namespace omniview {
namespace {

using namespace std::chrono_literals;

TEST(RefusalLog, ABurstPerPeerThenACountInTheNextWindow) {
  RefusalLog log(3, 10s);
  const auto t0 = RefusalLog::Clock::time_point{} + 1h;
  for (int i = 0; i < 3; ++i) EXPECT_EQ(log.admit("ipv4:10.0.0.7:4000", t0), 0u) << i;
  for (int i = 0; i < 500; ++i) EXPECT_FALSE(log.admit("ipv4:10.0.0.7:4000", t0 + 1s).has_value());
  // Another peer is not silenced by the first one's flood.
  EXPECT_EQ(log.admit("ipv4:10.0.0.8:4000", t0 + 2s), 0u);
  // A new window: one line again, saying how many were left out.
  EXPECT_EQ(log.admit("ipv4:10.0.0.7:4000", t0 + 10s), 500u);
  EXPECT_EQ(log.admit("ipv4:10.0.0.7:4000", t0 + 11s), 0u);
}

TEST(RefusalLog, AClientThatReconnectsIsStillOnePeer) {
  RefusalLog log(2, 10s);
  const auto t0 = RefusalLog::Clock::time_point{} + 1h;
  EXPECT_TRUE(log.admit("ipv4:10.0.0.7:4000", t0).has_value());
  EXPECT_TRUE(log.admit("ipv4:10.0.0.7:4001", t0).has_value());
  EXPECT_FALSE(log.admit("ipv4:10.0.0.7:4002", t0).has_value());
  EXPECT_FALSE(log.admit("ipv6:[::1]:4003", t0).has_value() && log.admit("ipv6:[::1]:4004", t0).has_value() &&
               log.admit("ipv6:[::1]:4005", t0).has_value());
  EXPECT_EQ(RefusalLog::peer_host("ipv4:10.0.0.7:4000"), "ipv4:10.0.0.7");
  EXPECT_EQ(RefusalLog::peer_host("ipv6:[::1]:4000"), "ipv6:[::1]");
  EXPECT_EQ(RefusalLog::peer_host("unix:/run/o.sock"), "unix:/run/o.sock");
}

TEST(RefusalLog, ManyPeersStayBounded) {
  RefusalLog log(1, 10s);
  const auto t0 = RefusalLog::Clock::time_point{} + 1h;
  for (int i = 0; i < 20000; ++i) log.admit("ipv4:10.0." + std::to_string(i / 250) + "." + std::to_string(i % 250) + ":1", t0);
  EXPECT_TRUE(log.admit("ipv4:192.168.0.1:1", t0).has_value());
}

}  // namespace
}  // namespace omniview
