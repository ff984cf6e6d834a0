// The web endpoint's small parts without a network: the outbox's order and newest-wins
// slots, static file confinement, upgrade requests (subprotocols and tokens).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "server/web/http/static_files.h"
#include "server/web/upgrade/upgrade_request.h"
#include "server/web/ws/outbox.h"

namespace omniview::web {
namespace {

namespace fs = std::filesystem;
namespace http = boost::beast::http;

OutMessage text(const std::string& s) {
  OutMessage m;
  m.head = s;
  return m;
}

TEST(Outbox, RepliesFirstThenChannelsInTurnNewestWins) {
  Outbox box(1 << 20);
  std::vector<std::string> dropped;
  const auto done = [&](const std::string& name) { return [&dropped, name](bool written) { if (!written) dropped.push_back(name); }; };
  box.push_latest(2, text("view-1"), done("view-1"));
  box.push_latest(2, text("view-2"), done("view-2"));  // replaces view-1: it never goes out
  box.push_latest(5, text("cloud-1"), done("cloud-1"));
  ASSERT_TRUE(box.push_text("reply"));
  EXPECT_EQ(dropped, std::vector<std::string>{"view-1"});
  std::vector<std::string> order;
  while (auto next = box.pop()) order.push_back(next->message.head);
  EXPECT_EQ(order, (std::vector<std::string>{"reply", "view-2", "cloud-1"}));
  // Round robin: channel 5 went last, so 2 goes next; then 5 before 2's newer message.
  box.push_latest(2, text("a"), nullptr);
  box.push_latest(5, text("b"), nullptr);
  EXPECT_EQ(box.pop()->message.head, "a");
  box.push_latest(2, text("c"), nullptr);
  EXPECT_EQ(box.pop()->message.head, "b");
  EXPECT_EQ(box.pop()->message.head, "c");
  EXPECT_TRUE(box.empty());
}

TEST(Outbox, BoundsUnreadRepliesAndDropsAllOnClose) {
  Outbox box(10);
  EXPECT_TRUE(box.push_text("12345"));
  EXPECT_TRUE(box.push_text("67890"));
  EXPECT_FALSE(box.push_text("x"));  // the client does not read: the session drops it
  bool called = false, written = true;
  box.push_latest(1, text("frame"), [&](bool w) { called = true; written = w; });
  box.drop_channels();  // closing: frames go, replies stay
  EXPECT_TRUE(called);
  EXPECT_FALSE(written);
  EXPECT_EQ(box.pop()->message.head, "12345");
  box.drop_all();
  EXPECT_TRUE(box.empty());
}

class StaticFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("omniview_static_" + std::to_string(::getpid()));
    fs::create_directories(root_ / "site" / "js");
    std::ofstream(root_ / "site" / "index.html") << "<html>";
    std::ofstream(root_ / "site" / "js" / "a.js") << "1";
    std::ofstream(root_ / "secret.txt") << "no";
    fs::create_symlink(root_ / "secret.txt", root_ / "site" / "link.txt");
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

TEST_F(StaticFilesTest, ServesInsideTheFoldersOnly) {
  StaticFiles files({{"/", (root_ / "site").string()}, {"/javascript/", ""}});
  auto f = files.find("/");
  EXPECT_EQ(f.status, 200);
  EXPECT_EQ(fs::path(f.file).filename(), "index.html");
  EXPECT_EQ(f.content_type, "text/html; charset=utf-8");
  f = files.find("/js/a.js?v=2");
  EXPECT_EQ(f.status, 200);
  EXPECT_EQ(f.content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(files.find("/../secret.txt").status, 400);
  EXPECT_EQ(files.find("/js/%2e%2e/%2e%2e/secret.txt").status, 400);
  EXPECT_EQ(files.find("/%zz").status, 400);
  EXPECT_EQ(files.find("/a%00b").status, 400);
  EXPECT_EQ(files.find("relative").status, 400);
  EXPECT_EQ(files.find("/link.txt").status, 404);  // a link out of the folder
  EXPECT_EQ(files.find("/nothing.html").status, 404);
  EXPECT_EQ(files.find("/javascript/three.js").status, 404);  // mount without a folder
}

http::request<http::string_body> upgrade_request(const std::string& target, const std::string& protocols,
                                                 const std::string& authorization = "") {
  http::request<http::string_body> r(http::verb::get, target, 11);
  if (!protocols.empty()) r.set(http::field::sec_websocket_protocol, protocols);
  if (!authorization.empty()) r.set(http::field::authorization, authorization);
  return r;
}

TEST(UpgradeRequest, SubprotocolsAndTokens) {
  auto u = parse_upgrade(upgrade_request("/ws", ""));
  EXPECT_EQ(u.protocol, WsProtocol::kConsole);
  EXPECT_EQ(u.answer, "");
  EXPECT_TRUE(u.tokens.empty());
  u = parse_upgrade(upgrade_request("/", "x-other, foxglove.sdk.v1 ,foxglove.websocket.v1"));
  EXPECT_EQ(u.protocol, WsProtocol::kFoxglove);
  EXPECT_EQ(u.answer, "foxglove.sdk.v1");  // the first served one, as offered
  u = parse_upgrade(upgrade_request("/", "foxglove.websocket.v1"));
  EXPECT_EQ(u.answer, "foxglove.websocket.v1");
  EXPECT_EQ(parse_upgrade(upgrade_request("/", "mqtt")).protocol, WsProtocol::kNone);
  u = parse_upgrade(upgrade_request("/?a=1&token=ab%2Bc%2F%3D&b", "omniview.console.v1"));
  EXPECT_EQ(u.protocol, WsProtocol::kConsole);
  EXPECT_EQ(u.tokens, std::vector<std::string>{"ab+c/="});
  u = parse_upgrade(upgrade_request("/?token=query", "", "Bearer header"));
  // Both are checked (a wrong one is refused even beside a good one); the header's decides the caller.
  EXPECT_EQ(u.tokens, (std::vector<std::string>{"header", "query"}));
  // Every one, wherever it repeats: a wrong second token is not hidden behind a good first.
  u = parse_upgrade(upgrade_request("/?token=good&x=1&token=wrong", ""));
  EXPECT_EQ(u.tokens, (std::vector<std::string>{"good", "wrong"}));
  http::request<http::string_body> two(http::verb::get, "/", 11);
  two.insert(http::field::authorization, "Bearer good");
  two.insert(http::field::authorization, "Bearer wrong");
  EXPECT_EQ(parse_upgrade(two).tokens, (std::vector<std::string>{"good", "wrong"}));
  u = parse_upgrade(upgrade_request("/", "", "Basic dXNlcg=="));
  EXPECT_EQ(u.tokens, std::vector<std::string>{""});  // malformed: refused as such, never "no token"
  EXPECT_EQ(query_value("/?token", "token"), std::nullopt);
  EXPECT_EQ(query_value("/?token=", "token"), "");
}

}  // namespace
}  // namespace omniview::web
