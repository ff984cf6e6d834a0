// `omniview show` on a virtual X display (Xvfb): keys and the mouse steer the view as a
// person would, through xdotool's synthetic X events.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "daemon_process.h"

extern char** environ;

namespace omniview::testing {
namespace {

using namespace std::chrono_literals;

template <typename F>
bool eventually(F&& done, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(50ms);
  }
  return done();
}

// A program run in the background (PATH searched), killed when it goes out of scope.
class ChildProcess {
 public:
  explicit ChildProcess(std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t quiet;
    posix_spawn_file_actions_init(&quiet);
    posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
    if (posix_spawnp(&pid_, argv[0], &quiet, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&quiet);
  }
  ~ChildProcess() {
    if (running()) ::kill(pid_, SIGTERM);
    if (pid_ > 0) ::waitpid(pid_, nullptr, 0);
  }
  bool running() { return pid_ > 0 && ::waitpid(pid_, &status_, WNOHANG) == 0; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
};

TEST(ShowWindow, KeysDragAndWheelSteerTheView) {
  TempDir dir;
  DaemonProcess daemon_(dir, example_config(20, "views:\n  - {name: front, type: perspective, width: 320, height: 160}\n"));
  const std::string display = ":" + std::to_string(70 + ::getpid() % 200);
  ChildProcess xvfb({"Xvfb", display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"});
  const std::string x = "env -u WAYLAND_DISPLAY DISPLAY=" + display + " ";
  ASSERT_TRUE(eventually([&] { return run_process(x + "xdotool getdisplaygeometry").exit_code == 0; }, std::chrono::milliseconds(static_cast<int64_t>(5000 * test_time_scale()))));
  ChildProcess show({"env", "-u", "WAYLAND_DISPLAY", "DISPLAY=" + display, OMNIVIEW_CLI, "show", "front", "--server",
                     daemon_.address()});
  // The window the first frame sized: only then does it take the mouse where the test
  // points. HighGUI may make and drop windows of that name while it starts, so every
  // match is asked, each time, until one has the frame's size.
  std::string window;
  ASSERT_TRUE(eventually([&] {
    std::istringstream ids(run_process(x + "xdotool search --name 'omniview: front'").output);
    for (std::string id; std::getline(ids, id);) {
      if (id.empty() || !std::isdigit(static_cast<unsigned char>(id[0]))) continue;
      if (run_process(x + "xdotool getwindowgeometry " + id).output.find("320x160") != std::string::npos) {
        window = id;
        return true;
      }
    }
    return false;
  }, std::chrono::milliseconds(static_cast<int64_t>(20000 * test_time_scale()))));
  const auto pose = [&] {
    v1::GetViewRequest get;
    get.set_name("front");
    v1::View view;
    auto stub = make_stub(daemon_.address());
    EXPECT_TRUE(stub->GetView(make_context().get(), get, &view).ok());
    return view.spec();
  };
  const v1::ViewSpec before = pose();
  // Dragging the picture 100 px right brings in what lies left: yaw + 100 * hfov / width.
  ASSERT_EQ(run_process(x + "xdotool windowfocus --sync " + window + " mousemove --window " + window +
                        " 100 80 mousedown 1 mousemove --window " + window + " 150 80 sleep 0.2 mousemove --window " +
                        window + " 200 80 sleep 0.2 mouseup 1").exit_code, 0);
  const double expected_yaw = before.yaw_deg() + 100 * before.hfov_deg() / 320;
  EXPECT_TRUE(eventually([&] { return std::abs(pose().yaw_deg() - expected_yaw) < 0.5; }, std::chrono::milliseconds(static_cast<int64_t>(5000 * test_time_scale()))))
      << pose().yaw_deg() << " vs " << expected_yaw;
  // A wheel notch away zooms in by 1.25; the 'w' key tilts up by 5 degrees.
  ASSERT_EQ(run_process(x + "xdotool mousemove --window " + window + " 100 80 click 4 sleep 0.3 windowfocus --sync " + window + " key w").exit_code, 0);
  const double zoomed_hfov = 2 * std::atan(std::tan(before.hfov_deg() * M_PI / 360) / 1.25) * 180 / M_PI;
  EXPECT_TRUE(eventually([&] {
    const auto now = pose();
    return std::abs(now.hfov_deg() - zoomed_hfov) < 0.1 && std::abs(now.pitch_deg() - (before.pitch_deg() - 5)) < 0.1;
  }, std::chrono::milliseconds(static_cast<int64_t>(5000 * test_time_scale())))) << pose().hfov_deg() << " vs " << zoomed_hfov << ", pitch " << pose().pitch_deg();
  run_process(x + "xdotool key --window " + window + " q");
  EXPECT_TRUE(eventually([&] { return !show.running(); }, std::chrono::milliseconds(static_cast<int64_t>(5000 * test_time_scale())))) << "q closes the window";
}

}  // namespace
}  // namespace omniview::testing
