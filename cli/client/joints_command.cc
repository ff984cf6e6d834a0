// `omniview joints [SOURCE] [NAME=VALUE ...]`: the joint positions the robot overlay draws,
// read or set (robots whose source does not report its joints).
#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

const std::string kJointsHelp = std::string(R"(usage: omniview joints [SOURCE] [NAME=VALUE ...] [--clear]

Shows the joint positions the robot overlay of SOURCE (default: the daemon's first source)
draws, and where each comes from: urdf (nobody set it: 0), config (robot_models[].joints),
api (set with this command), source (the robot reports it, as Spot does; it always wins).

With NAME=VALUE pairs (needs an operator token), sets those joints and keeps the others:
radians for revolute joints, metres for prismatic ones, or degrees with a 'deg' suffix
(fl.kn=-1.6 or fl.kn=-92deg).

  --clear     forget every position set through the API first (alone: back to config)

)") + connection_help();

// "fl.kn=-92deg" -> {"fl.kn", -1.6057}; `degrees` tells whether the value was in degrees.
std::pair<std::string, double> parse_assignment(const std::string& text, bool& degrees) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw UsageError("expected NAME=VALUE, got '" + text + "'");
  std::string value = text.substr(eq + 1);
  double scale = 1;
  degrees = value.size() > 3 && value.compare(value.size() - 3, 3, "deg") == 0;
  if (degrees) {
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
    std::string degrees;
    if (j.unit() == "rad") {
      degrees = "(";
      degrees += fixed(j.position() * 180 / std::numbers::pi, 1);
      degrees += " deg)";
    }
    table.add({j.name(), fixed(j.position(), 4) + " " + j.unit(), degrees, origin_text(j.origin())});
  }
  table.print(std::cout, "  ");
}

}  // namespace

int joints_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"clear"}, {}, kJointsHelp);
  if (!args) return 0;
  std::string source;
  v1::SetJointPositionsRequest set;
  std::vector<std::string> in_degrees;
  for (const auto& p : args->positional()) {
    if (p.find('=') == std::string::npos) {
      if (!source.empty() || set.positions_size() > 0) {
        throw UsageError("'" + p + "': expected NAME=VALUE (SOURCE comes first, once)");
      }
      source = p;
      continue;
    }
    bool degrees = false;
    const auto [name, value] = parse_assignment(p, degrees);
    if (set.positions().count(name)) throw UsageError("joint '" + name + "' given twice");
    (*set.mutable_positions())[name] = value;
    if (degrees) in_degrees.push_back(name);
  }
  Connection connection(connection_options(*args));
  const auto get = [&] {
    v1::GetJointPositionsRequest request;
    request.set_source(source);
    v1::JointPositions joints;
    grpc::ClientContext context;
    connection.prepare(context, true);
    connection.check(connection.stub().GetJointPositions(&context, request, &joints), "");
    return joints;
  };
  if (set.positions().empty() && !args->has("clear")) {
    print(get());
    return 0;
  }
  if (!in_degrees.empty()) {
    // Degrees only for angles: a prismatic joint's 'deg' would silently become metres.
    const v1::JointPositions known = get();
    for (const auto& j : known.joints()) {
      if (j.unit() != "rad" && std::find(in_degrees.begin(), in_degrees.end(), j.name()) != in_degrees.end()) {
        throw UsageError("joint '" + j.name() + "' is prismatic: give metres, not degrees");
      }
    }
  }
  set.set_source(source);
  set.set_clear(args->has("clear"));
  v1::JointPositions joints;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().SetJointPositions(&context, set, &joints), "");
  print(joints);
  // The source's own report wins: say so rather than seem to ignore the request.
  std::string overridden;
  for (const auto& j : joints.joints()) {
    if (j.origin() == v1::Joint::SOURCE && set.positions().count(j.name())) {
      overridden += (overridden.empty() ? "" : ", ") + j.name();
    }
  }
  if (!overridden.empty()) {
    std::cerr << "note: source '" << joints.source() << "' reports " << overridden
              << " itself, and what the robot reports wins; the values set here show only for joints it does not "
                 "report\n";
  }
  return 0;
}

}  // namespace omniview::cli
