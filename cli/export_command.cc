#include "cli/export_command.h"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include <opencv2/core/utils/logger.hpp>

#include "cli/args.h"
#include "cli/rig_args.h"
#include "core/view/view_yaml.h"
#include "server/config/daemon_config.h"
#include "server/export/mcap_export.h"

namespace omniview::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kExportHelp = R"(usage: omniview export RECORDING -o FILE.mcap [--config FILE | --view FILE ...] [options]

Writes a recording (the folder `omniview record` writes) as one MCAP file, which Foxglove
and Lichtblick open (README, "Open a recording in Foxglove"). Every message is stamped with
its capture time. Topics:
  /cameras/NAME/image, /cameras/NAME/calibration   the recorded images, as recorded
  /views/NAME, /views/NAME/calibration             each view rendered again from them
  /tf            the rig's frame tree and the views' poses
  /cloud         the recorded lidar clouds, coloured from the images
  /joint_states  the robot's joint positions (omniview.JointStates), where recorded

  -o, --out FILE      the MCAP file to write (replaced if it exists)
  --config FILE       render the views of a daemon config (those of the recording's
                      source by name; all its views when none names it)
  --view FILE         a view YAML (one view, or 'views: [...]'); repeatable
                      (without --config or --view no view is rendered)
  --encoding MODE     h264 (default: foxglove.CompressedVideo, a key frame a second) or
                      jpeg (foxglove.CompressedImage)
  --quality N         1..100 (default 50): JPEG quality, or H.264 as the streams' (CRF 26)
  --no-cameras        leave the recorded camera images out
  --no-clouds         leave the recorded clouds out
  --no-colour         the clouds as recorded, not coloured from the images
  --chunk-kb N        chunk size before zstd (default 1024: what readers seek by)
  -h, --help          this help
)";

const OptionSpec kExportOptions{.switches = {"no-cameras", "no-clouds", "no-colour", "no-color"},
                                .single = {"out", "config", "encoding", "quality", "chunk-kb"},
                                .repeatable = {"view"}};

std::vector<ViewSpec> views_of(const Args& args, const Recording& recording, std::vector<std::string>& notes) {
  std::vector<ViewSpec> views;
  std::map<std::string, std::string> defined_in;
  auto add = [&](const ViewSpec& spec, const std::string& where) {
    if (const auto it = defined_in.find(spec.name); it != defined_in.end()) {
      throw UsageError("view name '" + spec.name + "' is used twice: in " + it->second + " and in " + where +
                       "; view names must be unique");
    }
    defined_in[spec.name] = where;
    views.push_back(spec);
  };
  if (args.has("config")) {
    const DaemonConfig config = load_daemon_config(args.get("config"));
    std::vector<ViewSpec> mine;
    for (const auto& v : config.views) {
      if (v.source == recording.source_name) mine.push_back(v);
    }
    if (mine.empty() && !config.views.empty()) {
      notes.push_back("no view of " + args.get("config") + " names source '" + recording.source_name +
                      "' (the recording's): rendering all " + std::to_string(config.views.size()) + " of them");
      mine = config.views;
    }
    for (const auto& v : mine) add(v, args.get("config"));
  }
  for (const auto& file : args.all("view")) {
    for (const auto& v : load_views(file)) add(v, file);
  }
  return views;
}

}  // namespace

int export_command(const std::vector<std::string>& argv_in) {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  std::vector<std::string> argv = argv_in;
  for (auto& a : argv) {
    if (a == "-o") a = "--out";
  }
  const Args args = Args::parse(argv, kExportOptions);
  if (args.help_requested()) {
    std::cout << kExportHelp;
    return 0;
  }
  if (args.positional().empty()) throw UsageError("missing RECORDING (the folder `omniview record` wrote)");
  if (args.positional().size() > 1) throw UsageError("unexpected argument '" + args.positional()[1] + "'");
  const std::string out = args.required("out");
  if (fs::is_directory(out)) throw UsageError("--out " + out + " is a folder; give the MCAP file's name");

  export_mcap::ExportOptions options;
  const std::string encoding = args.get("encoding", "h264");
  if (encoding == "h264") {
    options.encoding = export_mcap::ViewEncoding::kH264;
  } else if (encoding == "jpeg") {
    options.encoding = export_mcap::ViewEncoding::kJpeg;
  } else {
    throw UsageError("--encoding must be 'h264' or 'jpeg', not '" + encoding + "'");
  }
  if (args.has("quality")) {
    const std::vector<double> q = parse_numbers(args.get("quality"), "--quality");
    if (q.size() != 1 || q[0] != static_cast<int>(q[0]) || q[0] < 1 || q[0] > 100) {
      throw UsageError("--quality must be a whole number in 1..100, not '" + args.get("quality") + "'");
    }
    options.quality = static_cast<int>(q[0]);
  }
  if (args.has("chunk-kb")) {
    const std::vector<double> kb = parse_numbers(args.get("chunk-kb"), "--chunk-kb");
    if (kb.size() != 1 || kb[0] != static_cast<int>(kb[0]) || kb[0] < 1 || kb[0] > 65536) {
      throw UsageError("--chunk-kb must be a whole number in 1..65536, not '" + args.get("chunk-kb") + "'");
    }
    options.chunk_bytes = static_cast<size_t>(kb[0]) * 1024;
  }
  options.cameras = !args.has("no-cameras");
  options.clouds = !args.has("no-clouds");
  options.colour_clouds = !args.has("no-colour") && !args.has("no-color");

  const std::string folder = args.positional()[0];
  const Recording recording = Recording::open(folder);
  std::vector<std::string> notes;
  options.views = views_of(args, recording, notes);
  if (options.views.empty()) notes.push_back("no views rendered (give --config or --view)");
  const bool tty = ::isatty(STDERR_FILENO);
  options.progress = [tty](size_t done, size_t total) {
    if (tty && (done % 10 == 0 || done == total)) std::cerr << "\romniview export: " << done << "/" << total << " frame sets" << std::flush;
  };
  const auto t0 = std::chrono::steady_clock::now();
  const export_mcap::ExportSummary summary = export_mcap::export_recording(recording, out, options);
  if (tty) std::cerr << "\n";
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double span = (summary.end_ns - summary.start_ns) / 1e9;
  notes.insert(notes.end(), summary.notes.begin(), summary.notes.end());
  for (const auto& n : notes) std::cerr << "omniview export: " << n << "\n";
  std::cout << std::fixed << std::setprecision(1) << out << ": " << summary.frame_sets << " frame sets over " << span
            << " s, " << summary.bytes / 1e6 << " MB, written in " << seconds << " s\n";
  for (const auto& [topic, count] : summary.messages) std::cout << "  " << topic << ": " << count << " messages\n";
  return 0;
}

}  // namespace omniview::cli
