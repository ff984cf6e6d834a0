// `omniview joints [SOURCE] [NAME=VALUE ...]`: the joint positions the robot overlay draws,
// read or set (robots whose source does not report its joints).
#include <cmath>
#include <iostream>
#include <numbers>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

const std::string kHelp = std::string(R"(usage: omniview joints [SOURCE] [NAME=VALUE ...] [--clear]

Shows the joint positions the robot overlay of SOURCE (default: the daemon's first source)
draws, and where each comes from: urdf (nobody set it: 0), config (robot_models[].joints),
api (set with this command), source (the robot reports it, as Spot does; it always wins).

With NAME=VALUE pairs (needs an operator token), sets those joints and keeps the others:
radians for revolute joints, metres for prismatic ones, or degrees with a 'deg' suffix
(fl.kn=-1.6 or fl.kn=-92deg).

  --clear     forget every position set through the API first (alone: back to config)

)") + connection_help();

// "fl.kn=-92deg" -> {"fl.kn", -1.6057}
std::pair<std::string, double> parse_assignment(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw UsageError("expected NAME=VALUE, got '" + text + "'");
  std::string value = text.substr(eq + 1);
  double scale = 1;
  if (value.size() > 3 && value.compare(value.size() - 3, 3, "deg") == 0) {
    value.resize(value.size() - 3);
    scale = std::numbers::pi / 180;
  }
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(v)) {
    throw UsageError(text.substr(0, eq) + ": expected a number (radians, metres, or degrees with 'deg'), got '" +
                     text.substr(eq + 1) + "'");
  }
  return {text.substr(0, eq), v * scale};
}

std::string origin_text(v1::Joint::Origin origin) {
  switch (origin) {
    case v1::Joint::CONFIG: return "config";
    case v1::Joint::API: return "api";
    case v1::Joint::SOURCE: return "source";
    default: return "urdf";
  }
}

void print(const v1::JointPositions& joints) {
  std::cout << "source '" << joints.source() << "', robot '" << joints.robot() << "':\n";
  if (joints.joints().empty()) {
    std::cout << "  no movable joints\n";
    return;
  }
  Table table({"JOINT", "POSITION", "", "FROM"});
  for (const auto& j : joints.joints()) {
    const bool angle = j.unit() == "rad";
    table.add({j.name(), fixed(j.position(), 4) + " " + j.unit(),
               angle ? "(" + fixed(j.position() * 180 / std::numbers::pi, 1) + " deg)" : "", origin_text(j.origin())});
  }
  table.print(std::cout, "  ");
}

}  // namespace

int joints_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"clear"}, {}, kHelp);
  if (!args) return 0;
  std::string source;
  v1::SetJointPositionsRequest set;
  for (const auto& p : args->positional()) {
    if (p.find('=') == std::string::npos) {
      if (!source.empty() || set.positions_size() > 0) {
        throw UsageError("'" + p + "': expected NAME=VALUE (SOURCE comes first, once)");
      }
      source = p;
      continue;
    }
    const auto [name, value] = parse_assignment(p);
    if (set.positions().count(name)) throw UsageError("joint '" + name + "' given twice");
    (*set.mutable_positions())[name] = value;
  }
  Connection connection(connection_options(*args));
  v1::JointPositions joints;
  grpc::ClientContext context;
  const std::string what = source.empty() ? "joints" : "joints of source '" + source + "'";
  if (set.positions().empty() && !args->has("clear")) {
    v1::GetJointPositionsRequest get;
    get.set_source(source);
    connection.prepare(context, true);
    connection.check(connection.stub().GetJointPositions(&context, get, &joints), what);
  } else {
    set.set_source(source);
    set.set_clear(args->has("clear"));
    connection.prepare(context, true);
    connection.check(connection.stub().SetJointPositions(&context, set, &joints), what);
  }
  print(joints);
  return 0;
}

}  // namespace omniview::cli
