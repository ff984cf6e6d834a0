// The one exposure rule (server/exposure): every spelling of an address, host names, unix
// sockets by their folder's mode, against every combination of guards. One table.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <filesystem>

#include "server/exposure/exposure_rule.h"
#include "test_support.h"

namespace omniview {
namespace {

namespace fs = std::filesystem;

// Names under .lan resolve here as a DNS server might answer; the rest asks the real resolver.
std::vector<std::string> fake_dns(const std::string& host, std::string* error) {
  if (host == "robot.lan") return {"192.168.1.7"};
  if (host == "loopback-only.lan") return {"127.0.0.5", "::1"};
  if (host == "split.lan") return {"127.0.0.1", "10.0.0.2"};  // one loopback, one not: refused
  if (host.ends_with(".lan")) {
    *error = "Name or service not known";
    return {};
  }
  return resolve_host(host, error);  // localhost, and numbers in inet_aton's forms (0, 0x0, 127.1)
}

enum class Expect { kOpen, kGuarded, kUnusable };  // allowed bare; needs tls+tokens; never starts

struct Row {
  std::string address;
  Expect expect;
  std::string says = "";  // in the refusal of the bare endpoint
};

void check_row(const Row& row) {
  SCOPED_TRACE(row.address);
  const auto refusal = [&](bool tls, bool tokens, bool allow) {
    return exposure_refusal({row.address, tls, tokens, allow}, fake_dns);
  };
  const std::string bare = refusal(false, false, false);
  switch (row.expect) {
    case Expect::kOpen:
      EXPECT_EQ(bare, "");
      break;
    case Expect::kGuarded:
      EXPECT_NE(bare.find(row.says), std::string::npos) << bare;
      EXPECT_NE(bare.find("neither tls nor tokens"), std::string::npos) << bare;
      EXPECT_NE(refusal(true, false, false).find("no tokens"), std::string::npos);
      EXPECT_NE(refusal(false, true, false).find("no tls"), std::string::npos);
      EXPECT_EQ(refusal(true, true, false), "");
      EXPECT_EQ(refusal(false, false, true), "");  // allow_insecure_remote: the operator's call
      break;
    case Expect::kUnusable:
      EXPECT_NE(bare.find(row.says), std::string::npos) << bare;
      EXPECT_NE(refusal(true, true, true), "") << "no guard makes it work";
      break;
  }
}

TEST(ExposureRule, EveryWayToSpellAnAddress) {
  const std::vector<Row> rows = {
      // Loopback, however written.
      {"127.0.0.1:50051", Expect::kOpen},
      {"127.1.2.3:0", Expect::kOpen},
      {"127.1:50051", Expect::kOpen},  // inet_aton's short form, as getaddrinfo reads it
      {"[::1]:50051", Expect::kOpen},
      {"[0:0:0:0:0:0:0:1]:50051", Expect::kOpen},
      {"[::ffff:127.0.0.1]:50051", Expect::kOpen},
      {"localhost:50051", Expect::kOpen},
      {"loopback-only.lan:50051", Expect::kOpen},
      // Every interface (IPv4 and IPv6 wildcards in every spelling), IPv4-mapped, other numbers.
      {"0.0.0.0:50051", Expect::kGuarded, "'0.0.0.0:50051' is reachable from other machines"},
      {"0:50051", Expect::kGuarded, "stands for 0.0.0.0"},
      {"0.0:50051", Expect::kGuarded, "reachable from other machines"},
      {"0x0:50051", Expect::kGuarded, "reachable from other machines"},
      {"[::]:50051", Expect::kGuarded, "reachable from other machines"},
      {"[0::0]:50051", Expect::kGuarded, "reachable from other machines"},
      {"[0:0:0:0:0:0:0:0]:50051", Expect::kGuarded, "reachable from other machines"},
      {"[::ffff:0.0.0.0]:50051", Expect::kGuarded, "reachable from other machines"},
      {"[::ffff:10.0.0.2]:50051", Expect::kGuarded, "reachable from other machines"},
      {"[::127.0.0.1]:50051", Expect::kGuarded, "reachable from other machines"},  // v4-compatible, not loopback
      {"10.0.0.2:50051", Expect::kGuarded, "reachable from other machines"},
      {"128.0.0.1:50051", Expect::kGuarded, "reachable from other machines"},
      {"[fe80::1]:50051", Expect::kGuarded, "reachable from other machines"},
      {":50051", Expect::kGuarded, "every interface"},
      // Host names: resolved, refused if any answer is not loopback.
      {"robot.lan:50051", Expect::kGuarded, "host 'robot.lan' stands for 192.168.1.7"},
      {"split.lan:50051", Expect::kGuarded, "stands for 10.0.0.2"},
      {"nowhere.lan:50051", Expect::kUnusable, "host 'nowhere.lan' in 'nowhere.lan:50051' does not resolve"},
      // Abstract unix sockets have no permissions at all.
      {"unix-abstract:omniview", Expect::kGuarded, "every user of this machine can connect"},
      {"unix:/nonexistent-folder/omniview.sock", Expect::kUnusable, "folder '/nonexistent-folder'"},
  };
  for (const auto& row : rows) check_row(row);
}

TEST(ExposureRule, AUnixSocketNeedsAFolderOnlyItsOwnerAndGroupCanEnter) {
  testing::TempDir dir;
  const fs::path tight = dir.path() / "tight", loose = dir.path() / "loose", group = dir.path() / "group";
  for (const auto& [folder, mode] : {std::pair{tight, 0700}, {loose, 0755}, {group, 0770}}) {
    fs::create_directories(folder);
    ASSERT_EQ(::chmod(folder.c_str(), mode), 0);
  }
  check_row({"unix:" + (tight / "o.sock").string(), Expect::kOpen});
  check_row({"unix://" + (tight / "o.sock").string(), Expect::kOpen});  // unix:///path, the URI form
  check_row({"unix:" + (group / "o.sock").string(), Expect::kOpen});
  check_row({"unix:" + (loose / "o.sock").string(), Expect::kGuarded, "(mode 0755) that every user of this machine can enter"});
  check_row({"unix:/tmp/omniview.sock", Expect::kGuarded, "folder '/tmp' (mode 1777)"});
  const std::string hint = exposure_refusal({"unix:" + (loose / "o.sock").string()});
  EXPECT_NE(hint.find("chmod o-rwx"), std::string::npos) << hint;
  // A relative path is judged by the working directory's mode.
  const fs::path cwd = fs::current_path();
  fs::current_path(tight);
  check_row({"unix:o.sock", Expect::kOpen});
  fs::current_path(loose);
  check_row({"unix:o.sock", Expect::kGuarded, "folder '.'"});
  fs::current_path(cwd);
}

TEST(ExposureRule, ABoundSocketIsMadeOwnerAndGroupOnly) {
  testing::TempDir dir;
  const std::string path = (dir.path() / "s.sock").string();
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", path.c_str());
  const mode_t old_mask = ::umask(0);  // as a careless service manager might start us
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ::umask(old_mask);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_NE(st.st_mode & S_IRWXO, 0u) << "the bind made it usable by others";
  restrict_unix_socket("unix:" + path);
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & S_IRWXO, 0u);
  EXPECT_EQ(st.st_mode & S_IRWXU, static_cast<mode_t>(S_IRWXU)) << "the owner keeps its rights";
  ::close(fd);
  EXPECT_NO_THROW(restrict_unix_socket("127.0.0.1:5"));  // not a socket file: nothing to do
  EXPECT_THROW(restrict_unix_socket("unix:" + (dir.path() / "gone.sock").string()), std::runtime_error);
}

TEST(ExposureRule, TheRealResolverAnswersForLocalhost) {
  std::string error;
  const auto numbers = resolve_host("localhost", &error);
  ASSERT_FALSE(numbers.empty()) << error;
  EXPECT_EQ(exposure_refusal({"localhost:50051"}), "");
}

}  // namespace
}  // namespace omniview
