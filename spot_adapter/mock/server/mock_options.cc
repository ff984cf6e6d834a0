#include "spot_adapter/mock/server/mock_options.h"

#include <cmath>
#include <iostream>
#include <stdexcept>

namespace omniview::spot_mock {

void print_mock_help() {
  std::cout <<
      "usage: spot-mock [options]\n"
      "       spot-mock control --port P --certs DIR [...]   (see spot-mock control --help)\n"
      "\n"
      "A stand-in Spot robot for CI, demos and newcomers: serves Spot's gRPC API (bosdyn.api\n"
      "AuthService, DirectoryService, RobotIdService, ImageService, PointCloudService,\n"
      "RobotStateService) over TLS on one port, with five Spot-like body cameras looking at a\n"
      "synthetic scene, a lidar, and omniview.spotmock.v1.SpotMockControl for fault injection.\n"
      "Clients connect as to a robot: trust DIR/ca.pem and set the TLS target name to the\n"
      "authority (api.spot.robot, auth.spot.robot, id.spot.robot).\n"
      "\n"
      "  --port N                     port to listen on (default 50443; 0: any free port)\n"
      "  --bind HOST                  address to listen on (default 127.0.0.1)\n"
      "  --certs DIR                  TLS files; made if missing: ca.pem (the CA clients trust) and\n"
      "                               <authority>.crt / <authority>.key (0600) per authority\n"
      "                               (default out/spot-mock, where config/spot.yaml looks)\n"
      "  --credentials FILE           YAML {username: ..., password: ...}; made if missing with\n"
      "                               username `user` and a random password, mode 0600\n"
      "                               (default out/spot-mock/credentials.yaml)\n"
      "  --token-lifetime-s S         lifetime of issued tokens (default 43200 = 12 h)\n"
      "  --lockout-s S                login lock after 6 bad logins in a row (default 60)\n"
      "  --scene room|test            room: a furnished room (default); test: bare test texture on\n"
      "                               the floor and on a wall x = 3 m (for golden comparisons)\n"
      "  --rgb                        a colour robot (RGB_U8); default greyscale like most Spots\n"
      "  --supersample N              rays per pixel along each axis when rendering (default 2)\n"
      "  --render-cache DIR           keep the rendered pictures and depth images in DIR and reuse\n"
      "                               them on later starts of this same spot-mock build with the\n"
      "                               same scene, colour and supersampling (the render is most of\n"
      "                               start-up; depth images are rendered at start, not on request)\n"
      "  --ready-file FILE            once serving, write HOST:PORT to FILE\n"
      "  --clock-offset-ms N          the robot's clock runs N ms ahead of this machine's (negative:\n"
      "                               behind); clients correct for it with TimeSyncService\n"
      "\n"
      "Faults (also settable at run time with `spot-mock control --set KEY=VALUE`):\n"
      "  --latency-ms N               added to every bosdyn.api call: half on the way in, half on\n"
      "                               the way back (after the robot stamped its times), as a link\n"
      "  --fail-probability P         GetImage fails (gRPC UNAVAILABLE or a header error)\n"
      "  --image-error-probability P  an image answers STATUS_IMAGE_DATA_ERROR\n"
      "  --corrupt-probability P      an image's bytes are truncated or garbled\n"
      "  --wrong-size-probability P   an image's cols/rows disagree with its data\n"
      "  --away                       every bosdyn.api call fails UNAVAILABLE\n"
      "\n"
      "  --help                       this text\n"
      "\n"
      "Stop with SIGTERM or Ctrl-C (exit 0). Passwords and tokens are never logged.\n";
}

double parse_double(const std::string& flag, const std::string& text) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
  }
  if (used == 0 || used != text.size() || !std::isfinite(v)) throw std::invalid_argument(flag + " needs a number");
  return v;
}

int parse_int(const std::string& flag, const std::string& text, int min, int max) {
  const double v = parse_double(flag, text);
  if (v != std::floor(v) || v < min || v > max) {
    throw std::invalid_argument(flag + " needs a whole number from " + std::to_string(min) + " to " +
                                std::to_string(max));
  }
  return static_cast<int>(v);
}

namespace {

double parse_probability(const std::string& flag, const std::string& text) {
  const double p = parse_double(flag, text);
  if (p < 0 || p > 1) throw std::invalid_argument(flag + " needs a probability from 0 to 1");
  return p;
}

}  // namespace

ParsedOptions parse_mock_options(const std::vector<std::string>& args) {
  MockOptions o;
  try {
    for (size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      const auto value = [&]() -> const std::string& {
        if (i + 1 >= args.size()) throw std::invalid_argument(arg + " needs a value");
        return args[++i];
      };
      FaultSettings& f = o.robot.faults;
      if (arg == "--help" || arg == "-h") {
        print_mock_help();
        return {std::nullopt, 0};
      } else if (arg == "--port") {
        o.port = parse_int(arg, value(), 0, 65535);
      } else if (arg == "--bind") {
        o.bind = value();
      } else if (arg == "--certs") {
        o.certs_dir = value();
      } else if (arg == "--credentials") {
        o.credentials_file = value();
      } else if (arg == "--token-lifetime-s") {
        o.robot.token_policy.token_lifetime = std::chrono::seconds(parse_int(arg, value(), 1, 365 * 86400));
      } else if (arg == "--lockout-s") {
        o.robot.token_policy.lockout = std::chrono::seconds(parse_int(arg, value(), 0, 86400));
      } else if (arg == "--scene") {
        const auto kind = parse_scene_kind(value());
        if (!kind) throw std::invalid_argument("--scene is room or test");
        o.robot.scene = *kind;
      } else if (arg == "--rgb") {
        o.robot.colour = true;
      } else if (arg == "--supersample") {
        o.robot.supersample = parse_int(arg, value(), 1, 8);
      } else if (arg == "--render-cache") {
        o.robot.render_cache = value();
      } else if (arg == "--ready-file") {
        o.ready_file = value();
      } else if (arg == "--latency-ms") {
        f.latency_ms = parse_int(arg, value(), 0, 60000);
      } else if (arg == "--fail-probability") {
        f.fail_probability = parse_probability(arg, value());
      } else if (arg == "--image-error-probability") {
        f.image_error_probability = parse_probability(arg, value());
      } else if (arg == "--corrupt-probability") {
        f.corrupt_probability = parse_probability(arg, value());
      } else if (arg == "--wrong-size-probability") {
        f.wrong_size_probability = parse_probability(arg, value());
      } else if (arg == "--clock-offset-ms") {
        o.clock_offset = std::chrono::milliseconds(parse_int(arg, value(), -86400000, 86400000));
      } else if (arg == "--away") {
        f.away = true;
      } else {
        throw std::invalid_argument("unknown argument '" + arg + "'");
      }
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "spot-mock: " << e.what() << " (see --help)\n";
    return {std::nullopt, 2};
  }
  return {o, 0};
}

}  // namespace omniview::spot_mock
