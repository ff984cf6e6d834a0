// `omniview show VIEW`: a live window of a view (OpenCV HighGUI) with keyboard and mouse
// pan, tilt and zoom, for an operator's laptop. Without a display it says so and names the pipe.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/display_probe.h"
#include "cli/client/frame_files.h"
#include "core/io/image_codec.h"

namespace omniview::cli {
namespace {

const std::string kShowHelp = std::string(R"(usage: omniview show VIEW [--step DEG] [--rate HZ] [--gray] [--quality Q]

Opens a window showing a view live. Keys and mouse (changing the view needs an operator
token):
  a / d, left / right   pan left / right by --step degrees (default 5)
  w / s, up / down      tilt up / down
  + / -                 zoom in / out (x1.25)
  drag                  pan and tilt: the picture follows the mouse
  wheel                 zoom in / out (x1.25 a notch)
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

// Drags and wheel notches since the view was last updated, from HighGUI's mouse callback
// (called on the same thread, inside waitKey).
struct MouseSteering {
  bool dragging = false;
  cv::Point last;
  double dx_px = 0, dy_px = 0;  // picture moved right / down
  int wheel_notches = 0;        // away from the user: zoom in

  static void on_event(int event, int x, int y, int flags, void* self) {
    auto& m = *static_cast<MouseSteering*>(self);
    if (event == cv::EVENT_LBUTTONDOWN) {
      m.dragging = true;
      m.last = {x, y};
    } else if (event == cv::EVENT_LBUTTONUP) {
      m.dragging = false;
    } else if (event == cv::EVENT_MOUSEMOVE && m.dragging && (flags & cv::EVENT_FLAG_LBUTTON)) {
      m.dx_px += x - m.last.x;
      m.dy_px += y - m.last.y;
      m.last = {x, y};
    } else if (event == cv::EVENT_MOUSEWHEEL) {
      m.wheel_notches += cv::getMouseWheelDelta(flags) > 0 ? 1 : -1;
    }
  }

  // The change the mouse asks for, `deg_per_px` degrees per pixel dragged; false if none.
  bool take(double deg_per_px, v1::ViewDelta& delta) {
    if (dx_px == 0 && dy_px == 0 && wheel_notches == 0) return false;
    // Dragging the picture right brings in what lies to the left (yaw is positive to the
    // left); dragging it down brings in what lies above (positive pitch looks down).
    delta.set_yaw_deg(dx_px * deg_per_px);
    delta.set_pitch_deg(-dy_px * deg_per_px);
    if (wheel_notches != 0) delta.set_zoom(std::pow(1.25, wheel_notches));
    dx_px = dy_px = 0;
    wheel_notches = 0;
    return true;
  }
};

// Degrees per pixel across the frame as rendered: a pinhole view's hfov over its width;
// a panorama's azimuth span; otherwise a tenth of a degree.
double degrees_per_pixel(const v1::Frame& frame) {
  const auto& spec = frame.camera().spec();
  if (frame.width() <= 0) return 0.1;
  if (spec.type() == v1::PERSPECTIVE && spec.hfov_deg() > 0) return spec.hfov_deg() / frame.width();
  if (spec.azimuth_span_deg() > 0 && spec.type() != v1::FISHEYE && spec.type() != v1::BIRDSEYE) {
    return spec.azimuth_span_deg() / frame.width();
  }
  return 0.1;
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
    // GUI_NORMAL: no toolbar, and Qt's own zoom does not take the wheel from us.
    cv::namedWindow(title, cv::WINDOW_AUTOSIZE | cv::WINDOW_GUI_NORMAL);
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
  MouseSteering mouse;
  cv::setMouseCallback(title, &MouseSteering::on_event, &mouse);
  // The revision our last update returned: a frame of an older one was already on its way
  // when the update took effect (docs/API.md, "Streams"), so the view never jumps back.
  uint64_t min_revision = 0;
  while (reader->Read(&frame)) {
    if (frames++ == 0) print_stream_note(context);
    if (frame.camera().revision() < min_revision) continue;
    const std::string& data = frame.data();
    cv::Mat image = decode_image(data);
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
    // One update per frame shown at most: the mouse's moves since the last one add up.
    if (delta_for_key(key, step, *update.mutable_delta()) || mouse.take(degrees_per_pixel(frame), *update.mutable_delta())) {
      v1::View view;
      grpc::ClientContext update_context;
      connection.prepare(update_context, true);
      const grpc::Status status = connection.stub().UpdateView(&update_context, update, &view);
      if (status.ok()) {
        min_revision = std::max(min_revision, view.revision());
      } else {
        // A viewer token cannot steer: say why once per key, keep showing.
        std::cerr << "omniview show: " << status.error_message() << "\n";
      }
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
