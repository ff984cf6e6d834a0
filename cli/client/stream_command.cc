// `omniview stream VIEW --frames N -o DIR`: frames of a view saved as files, with an index;
// `-o -`: the frames one after another on stdout (concatenated JPEGs are MJPEG for a pipe,
// concatenated H.264 access units a raw H.264 elementary stream).
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/frame_files.h"
#include "cli/client/stall_reporter.h"

namespace omniview::cli {
namespace {

const std::string kStreamHelp =
    std::string(R"(usage: omniview stream VIEW --frames N -o DIR [--encoding E] [--rate HZ] [--gray]
       omniview stream VIEW -o - [--frames N] | ffplay -f mjpeg -
       omniview stream VIEW --encoding h264 -o - | ffplay -

Saves N frames of a view as DIR/frame_000001.jpg, ... (the daemon's encoded bytes) and
DIR/frames.csv: file, sequence, capture time (UTC), latency (ms), size, view revision,
and last the share of the frame's pixels that stood on measured depth (0 for a view with
depth: fixed, or before any geometry came). With --encoding h264 the frames go into one
file, DIR/stream.h264 (a raw H.264 elementary stream, starting at a key frame; `ffplay
DIR/stream.h264`, or `ffmpeg -i DIR/stream.h264 -c copy out.mp4`), and frames.csv also
gives each frame's byte offset, size and whether it is a key frame (before that last column). Ctrl-C stops early and keeps what was written.

With -o - the frames go to stdout one after another, nothing between them: JPEG frames
make an MJPEG stream that `ffplay -f mjpeg -`, `mpv -` or `ffmpeg -f mjpeg -i -` read;
H.264 frames a raw H.264 stream that `ffplay -`, `mpv -` or `ffprobe -` read, low-latency
with `ffplay -fflags nobuffer -flags low_delay -framedrop -` (PNG frames: `ffplay -f
png_pipe -`; raw frames have no framing and are refused). It runs until --frames N,
Ctrl-C or the reader closes the pipe; messages go to stderr.

  --frames N         how many frames (optional with -o -)
  -o, --output DIR   the folder (created if missing; one with files in it is refused),
                     or - for stdout
  --force            write into a folder that has files, replacing its frames.csv and
                     frame_*.* files
)") +
    stream_help() + "\n" + connection_help();

std::string frame_file_name(uint64_t index, v1::Encoding encoding) {
  std::ostringstream name;
  name << "frame_" << std::setw(6) << std::setfill('0') << index << "." << extension_for(encoding);
  return name.str();
}

// Frames to stdout: each frame's bytes as sent, flushed at once so a player shows it now.
int stream_to_stdout(const Args& args, int wanted) {
  const auto request = stream_request(args, args.positional()[0], v1::JPEG);
  if (request.encoding() == v1::RAW) {
    throw UsageError("-o -: raw frames have no framing in a pipe; use --encoding jpg (MJPEG) or png");
  }
  // A reader that goes away (the player's window closed) ends the stream quietly: a write
  // error instead of SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  Connection connection(connection_options(args));
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, 0);
  auto reader = connection.stub().StreamFrames(&context, request);
  v1::Frame frame;
  int written = 0;
  bool reader_gone = false;
  StaleNotice stale(request.view());
  const bool video = request.encoding() == v1::H264;
  // No frame for a while (a robot away, a camera unplugged): why, on stderr, once a second.
  StallReporter stall(connection, request.view(), [](const std::string& why) { std::cerr << "waiting: " << why << "\n"; });
  while ((wanted == 0 || written < wanted) && reader->Read(&frame)) {
    stall.frame_arrived();
    // The player keeps showing the last picture; a video stream's frames are all needed
    // (each is coded against the one before), stale or not.
    if (stale.check(frame) && !video) continue;
    if (written == 0) print_stream_note(context);
    const std::string& data = frame.data();
    if (std::fwrite(data.data(), 1, data.size(), stdout) != data.size() || std::fflush(stdout) != 0) {
      reader_gone = true;
      break;
    }
    ++written;
  }
  if (reader_gone || (wanted > 0 && written == wanted)) stopper.stop();
  const grpc::Status status = reader->Finish();
  const bool failed = !status.ok() && !(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED);
  if (written > 0 || !failed) {
    std::cerr << "wrote " << written << " frame" << (written == 1 ? "" : "s") << " to stdout";
    if (reader_gone) std::cerr << " (the reader closed the pipe)";
    std::cerr << "\n";
  }
  if (failed) connection.check(status, view_label(request.view()));
  if (reader_gone) return 0;
  if (wanted > 0 && written < wanted) return stopper.interrupted() ? 130 : 1;
  return stopper.interrupted() ? 130 : 0;
}

}  // namespace

int stream_command(const std::vector<std::string>& argv) {
  std::vector<std::string> flags = stream_flags();
  flags.insert(flags.end(), {"frames", "output"});
  std::vector<std::string> switches = stream_switches();
  switches.push_back("force");
  const auto args = parse_command_args(argv, switches, flags, kStreamHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  if (args->has("output") && args->get("output") == "-") {
    // Binary video into a terminal garbles it; a person meant a pipe.
    if (::isatty(STDOUT_FILENO)) {
      throw UsageError("-o - writes a binary stream: pipe it into a player, e.g. omniview stream " +
                       args->positional()[0] + " -o - | ffplay -f mjpeg -");
    }
    return stream_to_stdout(*args, args->has("frames") ? parse_count(args->get("frames"), "--frames") : 0);
  }
  const int wanted = parse_count(args->required("frames"), "--frames");
  const std::filesystem::path folder = args->required("output");
  // Another run's frames.csv would be replaced and its frames mixed with these.
  std::error_code ec;
  if (!args->has("force") && std::filesystem::is_directory(folder, ec) &&
      !std::filesystem::is_empty(folder, ec)) {
    throw UsageError("'" + folder.string() +
                     "' is not empty: choose another folder, or pass --force to replace the frames in it");
  }
  const auto request = stream_request(*args, args->positional()[0], v1::JPEG);
  const bool video = request.encoding() == v1::H264;

  Connection connection(connection_options(*args));
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, 0);
  auto reader = connection.stub().StreamFrames(&context, request);
  v1::Frame frame;
  int written = 0;
  std::ofstream csv;
  std::ofstream stream_file;  // H.264: every frame into one elementary stream
  uint64_t offset = 0;
  const std::string stream_name = "stream.h264";
  StaleNotice stale(request.view());
  StallReporter stall(connection, request.view(), [](const std::string& why) { std::cerr << "waiting: " << why << "\n"; });
  while (written < wanted && reader->Read(&frame)) {
    stall.frame_arrived();
    // Not a new image; but a video stream needs every frame, and counts it.
    if (stale.check(frame) && !video) continue;
    if (written == 0) {  // only now: a wrong view name or a refused call leaves nothing behind
      print_stream_note(context);
      std::filesystem::create_directories(folder);
      csv.open(folder / "frames.csv", std::ios::trunc);
      if (!csv) throw std::runtime_error("cannot write '" + (folder / "frames.csv").string() + "'");
      csv << "file,sequence,capture_time,capture_time_s,latency_ms,width,height,channels,revision"
          << (video ? ",offset,bytes,key_frame" : "") << ",measured_depth\n";
      if (video) {
        stream_file.open(folder / stream_name, std::ios::binary | std::ios::trunc);
        if (!stream_file) throw std::runtime_error("cannot write '" + (folder / stream_name).string() + "'");
      }
    }
    std::string name = stream_name;
    if (video) {
      stream_file.write(frame.data().data(), static_cast<std::streamsize>(frame.data().size()));
      stream_file.flush();
      if (!stream_file) throw std::runtime_error("cannot write '" + (folder / stream_name).string() + "'");
    } else {
      name = frame_file_name(written + 1, frame.encoding());
      write_frame((folder / name).string(), frame);
    }
    csv << name << "," << frame.sequence() << "," << format_time(frame.capture_time()) << ","
        << fixed(to_seconds(frame.capture_time()), 6) << "," << fixed(frame.latency_ms(), 3) << "," << frame.width()
        << "," << frame.height() << "," << frame.channels() << "," << frame.camera().revision();
    if (video) csv << "," << offset << "," << frame.data().size() << "," << (frame.key_frame() ? 1 : 0);
    csv << "," << fixed(frame.measured_depth(), 3) << "\n" << std::flush;  // a stream cut short keeps a complete index
    offset += frame.data().size();
    ++written;
  }
  if (written == wanted) stopper.stop();  // the daemon ends the call when it sees the cancel
  const grpc::Status status = reader->Finish();
  const bool failed = !status.ok() && !(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED);
  // The summary first, also when the stream failed (daemon shutting down, source gone):
  // what was written stays usable.
  if (written > 0 || !failed) {
    std::cout << "wrote " << written << " frame" << (written == 1 ? "" : "s") << " to " << folder.string() << "/"
              << (video && written > 0 ? stream_name : "");
    if (written < wanted) {
      std::cout << " (" << (stopper.interrupted() ? "interrupted" : "the stream ended") << " before " << wanted << ")";
    }
    std::cout << "\n" << std::flush;
  }
  if (failed) connection.check(status, view_label(request.view()));
  if (written < wanted) return stopper.interrupted() ? 130 : 1;
  return 0;
}

}  // namespace omniview::cli
