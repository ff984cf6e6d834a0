// `omniview status`: the daemon's sources, views and clients.
#include <iostream>
#include <map>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

const std::string kStatusHelp = std::string(R"(usage: omniview status

Shows omniviewd's version and uptime, its sources (connected, rate, errors, skipped frame
sets), its views (subscribers, fps, map rebuilds, latency; for views with depth: measured
the geometry's age, the depth updates and the share of pixels on measured depth) and the
streaming clients.

)") + connection_help();

std::string age_text(double seconds) { return seconds < 0 ? "never" : fixed(seconds, 1) + " s"; }

std::string uptime_text(double s) {
  const auto total = static_cast<int64_t>(s);
  const int64_t days = total / 86400, hours = total % 86400 / 3600, minutes = total % 3600 / 60;
  std::string text = days ? std::to_string(days) + "d " : "";
  return text + std::to_string(hours) + "h " + std::to_string(minutes) + "m " + std::to_string(total % 60) + "s";
}

}  // namespace

int status_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {}, {}, kStatusHelp);
  if (!args) return 0;
  expect_positional(*args, 0, "");
  Connection connection(connection_options(*args));
  v1::Status status;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().GetStatus(&context, v1::GetStatusRequest(), &status), "status");

  std::cout << "omniviewd " << status.version() << " at " << connection.options().server << ", up "
            << uptime_text(status.uptime_s()) << "\n\nsources:\n";
  Table sources({"SOURCE", "TYPE", "CONNECTED", "RATE", "LAST FRAME", "FRAMES", "ERRORS", "SKIPPED", "ACTIVE CAMERAS",
                 "MESSAGE"});
  for (const auto& s : status.sources()) {
    std::string cameras;
    for (const auto& c : s.active_cameras()) cameras += (cameras.empty() ? "" : ",") + c;
    // Frames arriving while many calls fail is neither "yes" nor "NO".
    const std::string connected = !s.connected() ? "NO"
                                  : s.degraded() ? "degraded (" + fixed(100 * s.failure_rate(), 0) + "% failed)"
                                                 : "yes";
    sources.add({s.name(), s.type(), connected, fixed(s.rate_hz(), 1) + " Hz",
                 age_text(s.last_frame_age_s()), std::to_string(s.frames()), std::to_string(s.errors()),
                 std::to_string(s.dropped()), cameras.empty() ? "-" : cameras, s.message()});
  }
  sources.print(std::cout, "  ");

  std::cout << "\nviews:\n";
  if (status.views().empty()) {
    std::cout << "  none\n";
  } else {
    Table views({"VIEW", "SUBSCRIBERS", "FPS", "FRAMES", "MAP REBUILDS", "LAST BUILD", "COVERAGE", "LATENCY"});
    for (const auto& v : status.views()) {
      views.add({v.name(), std::to_string(v.subscribers()), fixed(v.fps(), 1), std::to_string(v.frames()),
                 std::to_string(v.map_rebuilds()), fixed(v.last_map_build_ms(), 1) + " ms",
                 v.map_pending() ? "(building)" : fixed(v.coverage() * 100, 1) + "%",
                 fixed(v.last_latency_ms(), 1) + " ms"});
    }
    views.print(std::cout, "  ");
    // A view's coverage means something once its source has delivered (a robot not yet
    // connected has no cameras: every view would read 0 %).
    std::map<std::string, bool> delivering;  // source -> connected and has delivered
    for (const auto& s : status.sources()) delivering[s.name()] = s.connected() && s.frames() > 0;
    std::map<std::string, std::string> source_of;  // view -> source
    std::map<std::string, bool> measured;          // view -> depth: measured
    v1::ListViewsResponse listed;
    grpc::ClientContext list_context;
    connection.prepare(list_context, true);
    if (connection.stub().ListViews(&list_context, v1::ListViewsRequest(), &listed).ok()) {
      for (const auto& v : listed.views()) {
        source_of[v.spec().name()] = v.spec().source();
        measured[v.spec().name()] = v.spec().depth() == v1::MEASURED;
      }
    }
    Table depth({"DEPTH VIEW", "GEOMETRY AGE", "UPDATES", "LAST UPDATE", "ON MEASURED DEPTH", "MESSAGE"});
    bool any_depth = false;
    for (const auto& v : status.views()) {
      if (!measured[v.name()]) continue;
      any_depth = true;
      depth.add({v.name(), age_text(v.depth_geometry_age_s()), std::to_string(v.depth_updates()),
                 fixed(v.depth_update_ms(), 1) + " ms", fixed(v.measured_depth() * 100, 1) + "%", v.depth_message()});
    }
    if (any_depth) {
      std::cout << "\n";
      depth.print(std::cout, "  ");
    }
    for (const auto& v : status.views()) {
      const auto source = source_of.find(v.name());
      if (source != source_of.end() && !delivering[source->second]) continue;
      if (v.map_pending()) continue;  // the coverage is the old map's
      const std::string warning = low_coverage_warning(v.name(), v.coverage());
      if (!warning.empty()) std::cout << "  warning: " << warning << "\n";
    }
  }

  if (!status.blackbox().empty()) {
    std::cout << "\nblack box (the last minutes, on the daemon's machine):\n";
    Table box({"SOURCE", "SPAN", "OF", "SIZE", "OF", "FRAME SETS", "NOT KEPT", "FOLDER"});
    for (const auto& b : status.blackbox()) {
      box.add({b.source(), fixed(b.span_s(), 1) + " s", fixed(b.minutes() * 60, 0) + " s",
               fixed(double(b.bytes()) / (1 << 20), 1) + " MiB", fixed(double(b.max_bytes()) / (1 << 20), 0) + " MiB",
               std::to_string(b.frame_sets()), std::to_string(b.not_kept()), b.folder()});
    }
    box.print(std::cout, "  ");
    for (const auto& b : status.blackbox()) {
      if (!b.message().empty()) std::cout << "  warning: black box of '" << b.source() << "': " << b.message() << "\n";
      if (!b.last_snapshot().empty()) std::cout << "  last snapshot of '" << b.source() << "': " << b.last_snapshot() << "\n";
    }
  }

  std::cout << "\nclients:\n";
  if (status.clients().empty()) {
    std::cout << "  none\n";
  } else {
    Table clients({"PEER", "VIEW", "ENCODING", "SENT", "DROPPED"});
    for (const auto& c : status.clients()) {
      clients.add(
          {c.peer(), c.view(), c.encoding(), std::to_string(c.frames_sent()), std::to_string(c.frames_dropped())});
    }
    clients.print(std::cout, "  ");
    // Not the sequence gaps 'omniview watch' shows as skipped (those include --rate).
    std::cout << "  (DROPPED: frames rendered for the client but replaced before it read them: it reads too slowly)\n";
  }
  return 0;
}

}  // namespace omniview::cli
