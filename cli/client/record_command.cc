// `omniview record -o DIR`: what a source delivers, written as a recording the `replay`
// source can play back.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/export_command.h"
#include "core/cloud/cloud_file.h"
#include "core/io/image_codec.h"
#include "core/io/yaml_reader.h"
#include "core/rig/rig.h"
#include "server/recording/recording.h"

namespace omniview::cli {
namespace {

const std::string kRecordHelp = std::string(R"(usage: omniview record -o DIR [--source NAME] [--frames N | --duration S]
       omniview record --format mcap -o FILE.mcap [--view VIEW.yaml ...] [--keep-recording] ...

Records what a source of omniviewd delivers (every camera image with capture times and
the rig) into DIR, a recording the 'replay' source plays back. Images are stored as the
source received them (a robot's JPEG byte for byte); those it has only as pixels, as
lossless PNG. Runs until N frame sets, S seconds, or Ctrl-C.

With --format mcap it writes one MCAP file for Foxglove and Lichtblick instead: it records
into FILE.mcap.recording/ as above and, when the recording ends, exports it as
`omniview export` does (cameras, calibrations, clouds, the frame tree, joints, and each view
rendered again as H.264), then removes that folder (--keep-recording keeps it). The views
are the daemon's views of the source as they were when recording began, or the --view
files'. Should the export fail, the recording stays and the message says where.

omniviewd queues frame sets for a recording that falls behind (a slow disk) up to its
limits.record_queue_frame_sets; beyond that it skips some, and this command says how many.

  -o, --output DIR   the recording folder (must not exist, or be empty)
  --source NAME      the source (default: the daemon's first)
  --frames N         stop after N frame sets
  --duration S       stop after S seconds
  --format F         dir (the default: a recording folder) or mcap
  --view FILE        mcap: a view YAML to render (repeatable; default: the daemon's views)
  --keep-recording   mcap: keep FILE.mcap.recording/ after the export

)") + connection_help();

std::string first_source(Connection& connection) {
  v1::Status status;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().GetStatus(&context, v1::GetStatusRequest(), &status), "status");
  if (status.sources().empty()) throw std::runtime_error("omniviewd has no sources");
  return status.sources(0).name();
}

// The bytes as the source delivered them; raw pixels (RGB) are stored as PNG.
RecordedImage to_recorded(const v1::CameraImage& image) {
  RecordedImage recorded{image.camera(), image.encoding() == v1::PNG ? "png" : "jpeg", {}};
  if (image.encoding() != v1::RAW) {
    recorded.bytes.assign(image.data().begin(), image.data().end());
    return recorded;
  }
  const int channels = image.channels();
  if ((channels != 1 && channels != 3) ||
      image.data().size() != static_cast<size_t>(image.width()) * image.height() * channels) {
    throw std::runtime_error("camera '" + image.camera() +
                             "': raw image size does not match its width, height and channels");
  }
  cv::Mat pixels(image.height(), image.width(), channels == 1 ? CV_8UC1 : CV_8UC3,
                 const_cast<char*>(image.data().data()));
  if (channels == 3) cv::cvtColor(pixels, pixels, cv::COLOR_RGB2BGR);
  recorded.bytes = encode_png(pixels);
  recorded.format = "png";
  return recorded;
}

// The daemon's views of `source` (all of them when none names it), each as a view file in
// `folder`, for the export.
std::vector<std::string> save_daemon_views(Connection& connection, const std::string& source,
                                           const std::filesystem::path& folder) {
  v1::ListViewsResponse listed;
  grpc::ClientContext context;
  connection.prepare(context, true);
  connection.check(connection.stub().ListViews(&context, v1::ListViewsRequest(), &listed), "views");
  std::vector<std::string> files;
  std::filesystem::create_directories(folder);
  for (const auto& v : listed.views()) {
    if (v.spec().source() != source) continue;
    const auto file = folder / ("view_" + std::to_string(files.size()) + ".yaml");
    std::ofstream(file) << v.yaml();
    files.push_back(file.string());
  }
  return files;
}

std::chrono::system_clock::time_point to_time_point(const google::protobuf::Timestamp& t) {
  return std::chrono::system_clock::time_point(std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::seconds(t.seconds()) + std::chrono::nanoseconds(t.nanos())));
}

}  // namespace

int record_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"keep-recording"}, {"output", "source", "frames", "duration", "format", "view"},
                                      kRecordHelp);
  if (!args) return 0;
  expect_positional(*args, 0, "");
  const std::string format = args->get("format", "dir");
  if (format != "dir" && format != "mcap") throw UsageError("--format must be 'dir' or 'mcap', not '" + format + "'");
  const bool mcap = format == "mcap";
  if (!mcap && (args->has("view") || args->has("keep-recording"))) {
    throw UsageError(std::string(args->has("view") ? "--view" : "--keep-recording") + " is for --format mcap");
  }
  const std::filesystem::path mcap_file = mcap ? std::filesystem::path(args->required("output")) : std::filesystem::path();
  if (mcap && std::filesystem::exists(mcap_file)) {
    throw UsageError("--output '" + mcap_file.string() + "' exists; remove it or give another name");
  }
  const std::filesystem::path folder = mcap ? std::filesystem::path(mcap_file.string() + ".recording")
                                            : std::filesystem::path(args->required("output"));
  if (args->has("frames") && args->has("duration")) throw UsageError("give --frames or --duration, not both");
  const int wanted = args->has("frames") ? parse_count(args->get("frames"), "--frames") : 0;
  const double duration_s = args->has("duration") ? parse_positive(args->get("duration"), "--duration") : 0;
  if (std::filesystem::exists(folder) &&
      (!std::filesystem::is_directory(folder) || !std::filesystem::is_empty(folder))) {
    throw UsageError("--output '" + folder.string() + "' exists and is not an empty folder");
  }

  Connection connection(connection_options(*args));
  const std::string source = args->has("source") ? args->get("source") : first_source(connection);
  // The views to render, as they are now (before the recording: a view changed while it
  // runs is rendered as it was when it began).
  std::vector<std::string> view_files;
  if (mcap) {
    view_files = args->has("view") ? args->all("view")
                                   : save_daemon_views(connection, source, std::filesystem::path(mcap_file.string() + ".views"));
  }
  v1::StreamSourceFramesRequest request;
  request.set_source(source);
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, duration_s);
  auto reader = connection.stub().StreamSourceFrames(&context, request);

  std::optional<RecordingWriter> writer;  // created on the first frame: a refused call leaves no folder
  std::optional<Rig> rig;
  const bool tty = isatty(STDOUT_FILENO);
  v1::SourceFrame frame;
  size_t written = 0;
  uint64_t skipped = 0;  // by the daemon, before the last frame set written
  while ((wanted == 0 || written < static_cast<size_t>(wanted)) && reader->Read(&frame)) {
    if (!frame.rig_yaml().empty()) {
      // Mask paths in the rig are the daemon's; they resolve against its config folder.
      const auto yaml = YamlReader::from_string(frame.rig_yaml(), "the rig omniviewd sent");
      rig = parse_rig_yaml(yaml, ".");
    }
    if (!rig) throw std::runtime_error("omniviewd sent a frame set before the rig; cannot record it");
    std::vector<RecordedImage> images;
    for (const auto& image : frame.images()) images.push_back(to_recorded(image));
    if (!writer) writer.emplace(folder.string(), source);
    if (!frame.joint_positions().empty()) {
      writer->set_next_joints({frame.joint_positions().begin(), frame.joint_positions().end()});
    }
    if (!frame.cloud_pcd().empty()) {
      writer->set_next_cloud(std::make_shared<const PointCloud>(parse_pcd(frame.cloud_pcd(), "the cloud omniviewd sent")));
    }
    writer->write(frame.sequence(), to_time_point(frame.capture_time()), *rig, images);
    ++written;
    skipped = frame.skipped();
    if (tty && written % 10 == 0) {
      std::cout << "\r\033[Krecorded " << written << " frame sets, skipped " << skipped << std::flush;
    }
  }
  if (tty && written >= 10) std::cout << "\n";
  if (wanted > 0 && written == static_cast<size_t>(wanted)) stopper.stop();
  const grpc::Status status = reader->Finish();
  if (writer) writer->close();
  if (!(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED)) {
    connection.check(status, "source '" + source + "'");
  }
  std::cout << "recorded " << written << " frame set" << (written == 1 ? "" : "s") << ", skipped " << skipped
            << ", of source '" << source << "' to " << folder.string() << "/\n";
  if (skipped > 0) {
    std::cerr << "omniview record: omniviewd skipped " << skipped << " frame set" << (skipped == 1 ? "" : "s")
              << " while this recording was behind by more than its queue (limits.record_queue_frame_sets): "
                 "the gaps show in frames.csv's sequence numbers. A faster disk, or a lower source rate, avoids "
                 "them.\n";
  }
  if (!mcap || written == 0) return written > 0 ? 0 : 1;

  std::vector<std::string> export_args = {folder.string(), "-o", mcap_file.string()};
  for (const auto& f : view_files) export_args.insert(export_args.end(), {"--view", f});
  try {
    export_command(export_args);
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string(e.what()) + " (the recording is kept in " + folder.string() +
                             "/: omniview export can write it again)");
  }
  if (!args->has("view")) std::filesystem::remove_all(mcap_file.string() + ".views");
  if (!args->has("keep-recording")) std::filesystem::remove_all(folder);
  return 0;
}

}  // namespace omniview::cli
