// `omniview show VIEW`: a live window of a view (OpenCV HighGUI) with keyboard pan, tilt
// and zoom, for an operator's laptop. Without a display it says so and names the pipe.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>

#include <opencv2/highgui.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/display_probe.h"
#include "cli/client/frame_files.h"

namespace omniview::cli {
namespace {

const std::string kShowHelp = std::string(R"(usage: omniview show VIEW [--step DEG] [--rate HZ] [--gray] [--quality Q]

Opens a window showing a view live. Keys (changing the view needs an operator token):
  a / d, left / right   pan left / right by --step degrees (default 5)
  w / s, up / down      tilt up / down
  + / -                 zoom in / out (x1.25)
  q, Esc                quit (so does closing the window)

Needs a display (DISPLAY or WAYLAND_DISPLAY); over ssh use 'ssh -X', or pipe the view into
a player instead: omniview stream VIEW -o - | ffplay -f mjpeg -

  --step DEG         degrees per pan or tilt key (default 5)
)") + stream_help() + "\n" + connection_help();

bool has_display() {
  for (const char* name : {"DISPLAY", "WAYLAND_DISPLAY"}) {
    const char* value = std::getenv(name);
    if (value && *value) return true;
  }
  return false;
}

// The view change a key asks for; false for keys that change nothing.
bool delta_for_key(int key, double step, v1::ViewDelta& delta) {
  // HighGUI's codes for the arrow keys (GTK and Qt back ends) besides the letters.
  switch (key) {
    case 'a': case 81: case 65361: delta.set_yaw_deg(step); return true;     // pan left: yaw is positive to the left
    case 'd': case 83: case 65363: delta.set_yaw_deg(-step); return true;
    case 'w': case 82: case 65362: delta.set_pitch_deg(-step); return true;  // up: positive pitch looks down
    case 's': case 84: case 65364: delta.set_pitch_deg(step); return true;
    case '+': case '=': delta.set_zoom(1.25); return true;
    case '-': case '_': delta.set_zoom(1 / 1.25); return true;
    default: return false;
  }
}

// A red band across the top with the reason: the picture is the last one the source gave.
void draw_stale_banner(cv::Mat& image, const std::string& reason) {
  if (image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
  const int band = std::max(18, image.rows / 24);
  cv::rectangle(image, {0, 0, image.cols, band}, cv::Scalar(0, 0, 160), cv::FILLED);
  cv::putText(image, "STALE: " + reason, {6, band * 3 / 4}, cv::FONT_HERSHEY_SIMPLEX, band / 36.0,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

}  // namespace

int show_command(const std::vector<std::string>& argv) {
  std::vector<std::string> flags = stream_flags();
  flags.push_back("step");
  const auto args = parse_command_args(argv, stream_switches(), flags, kShowHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  const double step = args->has("step") ? parse_positive(args->get("step"), "--step") : 5;
  auto request = stream_request(*args, args->positional()[0], v1::JPEG);
  if (request.encoding() == v1::RAW || request.encoding() == v1::H264) {
    throw UsageError(
        "--encoding: show decodes jpg or png (for h264: omniview stream VIEW --encoding h264 -o - | ffplay -)");
  }
  const std::string instead =
      "over ssh use 'ssh -X', or pipe the view into a player: omniview stream " + request.view() + " -o - | ffplay -f mjpeg -";
  if (!has_display()) {
    throw std::runtime_error("no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset): " + instead);
  }
  // HighGUI aborts the whole process on a display it cannot reach: ask it first.
  if (const char* display = std::getenv("DISPLAY"); display && *display) {
    if (const std::string why = probe_x_display(display); !why.empty()) {
      throw std::runtime_error("no display to open a window on (" + why + "): " + instead);
    }
  }
  const std::string title = "omniview: " + request.view();
  try {
    cv::namedWindow(title, cv::WINDOW_AUTOSIZE);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("cannot open a window: " + std::string(e.what()));
  }

  Connection connection(connection_options(*args));
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, 0);
  auto reader = connection.stub().StreamFrames(&context, request);
  v1::Frame frame;
  uint64_t frames = 0;
  StaleNotice stale(request.view());
  while (reader->Read(&frame)) {
    if (frames++ == 0) print_stream_note(context);
    const std::string& data = frame.data();
    cv::Mat image = cv::imdecode(std::vector<uchar>(data.begin(), data.end()), cv::IMREAD_UNCHANGED);
    // The last picture again (still steerable): marked, so nobody takes it for live.
    if (stale.check(frame) && !image.empty()) draw_stale_banner(image, frame.stale_reason());
    if (!image.empty()) cv::imshow(title, image);
    const int key = cv::waitKeyEx(1);
    if (key == 'q' || key == 27 || cv::getWindowProperty(title, cv::WND_PROP_VISIBLE) < 1) {
      stopper.stop();
      break;
    }
    v1::UpdateViewRequest update;
    update.set_name(request.view());
    if (delta_for_key(key, step, *update.mutable_delta())) {
      v1::View view;
      grpc::ClientContext update_context;
      connection.prepare(update_context, true);
      const grpc::Status status = connection.stub().UpdateView(&update_context, update, &view);
      // A viewer token cannot steer: say why once per key, keep showing.
      if (!status.ok()) std::cerr << "omniview show: " << status.error_message() << "\n";
    }
  }
  const grpc::Status status = reader->Finish();
  cv::destroyAllWindows();
  if (!status.ok() && !(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED)) {
    connection.check(status, view_label(request.view()));
  }
  return stopper.interrupted() ? 130 : 0;
}

}  // namespace omniview::cli
