#include "spot_adapter/mock/auth/certificates.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace omniview::spot_mock {
namespace fs = std::filesystem;
namespace {

// Runs `openssl args...` in `work` (no shell, so paths need no quoting); throws with its
// output on failure.
void openssl(const fs::path& work, std::vector<std::string> args) {
  args.insert(args.begin(), "openssl");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const fs::path log = work / "openssl.log";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addchdir_np(&actions, work.c_str());
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, "openssl", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) throw std::runtime_error("cannot run `openssl` (is it installed?) to make the mock's certificates");
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::ifstream in(log);
    std::stringstream out;
    out << in.rdbuf();
    throw std::runtime_error("`openssl " + args[1] + "` failed making the mock's certificates: " + out.str());
  }
}

void new_key(const fs::path& work, const std::string& file) {
  openssl(work, {"ecparam", "-name", "prime256v1", "-genkey", "-noout", "-out", file});
}

void make_ca(const fs::path& work) {
  new_key(work, "ca.key");
  openssl(work, {"req", "-new", "-x509", "-key", "ca.key", "-subj", "/CN=spot-mock CA", "-days", "3650", "-sha256",
                 "-addext", "basicConstraints=critical,CA:TRUE", "-addext", "keyUsage=critical,keyCertSign,cRLSign",
                 "-out", "ca.pem"});
}

void make_server_cert(const fs::path& work, const std::string& authority) {
  new_key(work, authority + ".key");
  openssl(work, {"req", "-new", "-key", authority + ".key", "-subj", "/CN=" + authority, "-out", authority + ".csr"});
  std::ofstream(work / (authority + ".ext")) << "basicConstraints=CA:FALSE\n"
                                                "keyUsage=critical,digitalSignature\n"
                                                "extendedKeyUsage=serverAuth\n"
                                                "subjectAltName=DNS:"
                                             << authority << "\n";
  openssl(work, {"x509", "-req", "-in", authority + ".csr", "-CA", "ca.pem", "-CAkey", "ca.key", "-CAcreateserial",
                 "-CAserial", "ca.srl", "-days", "3650", "-sha256", "-extfile", authority + ".ext", "-out",
                 authority + ".crt"});
}

}  // namespace

const std::vector<std::string>& mock_authorities() {
  static const std::vector<std::string> authorities = {"api.spot.robot", "auth.spot.robot", "id.spot.robot"};
  return authorities;
}

std::string ca_cert_file(const std::string& dir) { return (fs::path(dir) / "ca.pem").string(); }
std::string cert_file(const std::string& dir, const std::string& authority) {
  return (fs::path(dir) / (authority + ".crt")).string();
}
std::string key_file(const std::string& dir, const std::string& authority) {
  return (fs::path(dir) / (authority + ".key")).string();
}

bool ensure_certificates(const std::string& dir) {
  bool complete = fs::exists(ca_cert_file(dir));
  for (const auto& a : mock_authorities()) complete = complete && fs::exists(cert_file(dir, a)) && fs::exists(key_file(dir, a));
  if (complete) return false;

  fs::create_directories(dir);
  // Work in a private folder (keys are never readable by others, even half-written), then
  // move the results in; the CA key and the requests stay behind and are deleted.
  const fs::path work = fs::path(dir) / ".spot-mock-certs.tmp";
  fs::remove_all(work);
  fs::create_directory(work);
  fs::permissions(work, fs::perms::owner_all, fs::perm_options::replace);
  try {
    make_ca(work);
    for (const auto& a : mock_authorities()) make_server_cert(work, a);
    for (const auto& a : mock_authorities()) {
      fs::permissions(work / (a + ".key"), fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
      fs::rename(work / (a + ".key"), key_file(dir, a));
      fs::rename(work / (a + ".crt"), cert_file(dir, a));
    }
    fs::rename(work / "ca.pem", ca_cert_file(dir));
  } catch (...) {
    fs::remove_all(work);
    throw;
  }
  fs::remove_all(work);
  return true;
}

}  // namespace omniview::spot_mock
