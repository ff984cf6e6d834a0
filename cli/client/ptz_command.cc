// `omniview ptz VIEW`: pan, tilt and zoom a view, absolutely or by steps.
#include <cmath>
#include <iostream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/view_spec_proto.h"

namespace omniview::cli {
namespace {

const std::string kPtzHelp = std::string(
                              R"(usage: omniview ptz VIEW [--pan DEG] [--tilt DEG] [--roll DEG] [--zoom X | --hfov DEG]
       omniview ptz VIEW --relative [--pan DEG] [--tilt DEG] [--roll DEG] [--zoom X]
       omniview ptz VIEW [--dpan DEG] [--dtilt DEG] [--droll DEG] [--dzoom X]

Points a view (needs an operator token) and prints where it then looks. With no
change, prints the view's current pan, tilt and field of view.

  --pan DEG       yaw, positive turns left
  --tilt DEG      pitch, positive looks down, in [-90, 90]; steps stop at straight down
                  (90) or up (-90)
  --roll DEG      roll
  --zoom X        perspective and birdseye views: zoom 1 is a 90 deg horizontal field of
                  view, zoom X has X times its focal length (hfov = 2 atan(1 / X))
  --hfov DEG      the horizontal field of view itself (perspective and birdseye views)
  --relative      --pan, --tilt, --roll and --zoom are steps from where the view is
                  (zoom 2 doubles the focal length; fisheye views halve their fov_deg)
  --dpan, --dtilt, --droll DEG, --dzoom X
                  steps, as with --relative

Panoramas (cylindrical, mercator, equirectangular) have no zoom: narrow one with
'omniview views update VIEW --set azimuth_span_deg=DEG' (and vfov_deg for cylindrical,
lat_min_deg/lat_max_deg for the others).

)") + connection_help();

double number(const Args& args, const std::string& name) {
  const std::string text = args.get(name);
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v)) {
    throw UsageError("--" + name + ": expected a number, got '" + text + "'");
  }
  return v;
}

// "front: pan 10.0, tilt 5.0, roll 0.0 deg, hfov 60.0 deg (zoom 1.73x), revision 7"
std::string describe(const v1::View& view) {
  const auto& s = view.spec();
  std::string line = s.name() + ": pan " + fixed(s.yaw_deg(), 2) + ", tilt " + fixed(s.pitch_deg(), 2) + ", roll " +
                     fixed(s.roll_deg(), 2) + " deg";
  if (s.type() == v1::PERSPECTIVE || s.type() == v1::BIRDSEYE) {
    line += ", hfov " + fixed(s.hfov_deg(), 2) + " deg (zoom " + fixed(zoom_from_hfov(s.hfov_deg()), 2) + "x)";
  } else if (s.type() == v1::FISHEYE) {
    line += ", fov " + fixed(s.fov_deg(), 2) + " deg";
  }
  return line + ", revision " + std::to_string(view.revision());
}

v1::View get_view(Connection& connection, const std::string& name) {
  v1::GetViewRequest request;
  request.set_name(name);
  v1::View view;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().GetView(&context, request, &view), view_label(name));
  return view;
}

}  // namespace

int ptz_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(
      argv, {"relative"}, {"pan", "tilt", "roll", "zoom", "hfov", "dpan", "dtilt", "droll", "dzoom"}, kPtzHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  const std::string name = args->positional()[0];
  const bool relative = args->has("relative");
  if (args->has("zoom") && args->has("hfov")) throw UsageError("give --zoom or --hfov, not both");
  if (relative && args->has("hfov")) throw UsageError("--hfov is absolute; use --zoom or --dzoom for steps");
  for (const char* zoom : {"zoom", "dzoom"}) {
    if (args->has(zoom) && !(number(*args, zoom) > 0)) throw UsageError(std::string("--") + zoom + ": must be > 0");
  }

  v1::UpdateViewRequest request;
  request.set_name(name);
  auto& set = *request.mutable_set();
  auto& delta = *request.mutable_delta();
  if (!relative) {
    if (args->has("pan")) set.set_yaw_deg(number(*args, "pan"));
    if (args->has("tilt")) set.set_pitch_deg(number(*args, "tilt"));
    if (args->has("roll")) set.set_roll_deg(number(*args, "roll"));
    if (args->has("zoom")) set.set_hfov_deg(hfov_from_zoom(number(*args, "zoom")));
  }
  if (args->has("hfov")) set.set_hfov_deg(number(*args, "hfov"));
  // Steps: --dpan and friends always, --pan and friends with --relative.
  const auto step = [&](const char* flag, const char* step_flag, double none, auto combine) {
    double v = args->has(step_flag) ? number(*args, step_flag) : none;
    return relative && args->has(flag) ? combine(v, number(*args, flag)) : v;
  };
  const auto add = [](double a, double b) { return a + b; };
  delta.set_yaw_deg(step("pan", "dpan", 0, add));
  delta.set_pitch_deg(step("tilt", "dtilt", 0, add));
  delta.set_roll_deg(step("roll", "droll", 0, add));
  const double zoom_step = step("zoom", "dzoom", 1, [](double a, double b) { return a * b; });
  delta.set_zoom(zoom_step == 1 ? 0 : zoom_step);

  Connection connection(connection_options(*args));
  const bool changes = set.ByteSizeLong() > 0 || delta.ByteSizeLong() > 0;
  if (!changes) {
    std::cout << describe(get_view(connection, name)) << "\n";
    return 0;
  }
  if (set.has_hfov_deg() || delta.zoom() != 0) {
    // Say what zooms this view rather than let the daemon refuse a key it does not have.
    const auto type = get_view(connection, name).spec().type();
    if (type == v1::FISHEYE && set.has_hfov_deg()) {
      throw UsageError("view '" + name + "' is a fisheye view: zoom it with --relative --zoom X (or --dzoom X), "
                       "or set its field of view with 'omniview views update " + name + " --set fov_deg=DEG'");
    }
    if (type != v1::PERSPECTIVE && type != v1::BIRDSEYE && type != v1::FISHEYE) {
      throw UsageError("view '" + name + "' is a " + to_string(from_proto(type, view_label(name))) +
                       " panorama, which has no zoom: narrow it with 'omniview views update " + name +
                       " --set azimuth_span_deg=DEG'" +
                       (type == v1::CYLINDRICAL ? " (and vfov_deg)" : " (and lat_min_deg, lat_max_deg)"));
    }
  }
  v1::View view;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().UpdateView(&context, request, &view), view_label(name));
  std::cout << describe(view) << "\n";
  if (delta.pitch_deg() != 0 && std::abs(view.spec().pitch_deg()) == 90) {
    std::cout << "(tilt stops at " << (view.spec().pitch_deg() > 0 ? "90 deg, straight down" : "-90 deg, straight up")
              << "; pan by 180 to look behind)\n";
  }
  return 0;
}

}  // namespace omniview::cli
