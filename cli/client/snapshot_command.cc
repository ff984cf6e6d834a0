// `omniview snapshot VIEW -o FILE`: the next frame of a view, saved as the server encodes it
// (`-o -`: to stdout, for a pipe).
#include <cstdio>
#include <iostream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/frame_files.h"

namespace omniview::cli {
namespace {

const std::string kSnapshotHelp =
    std::string(R"(usage: omniview snapshot VIEW -o OUT.png|OUT.jpg|OUT.raw [--gray] [--quality Q] [--wait S]
       omniview snapshot VIEW -o - [--encoding jpg|png|raw] > frame.jpg

Saves the next frame of a view. The extension chooses the encoding; .raw is the pixels
as they are (rows top to bottom, 8-bit RGB or gray; the size is printed).

  -o, --output FILE  where to write; - writes the image to stdout (JPEG unless
                     --encoding says otherwise) and the description to stderr
  --encoding E       jpg, png or raw, for -o - (a file's extension chooses otherwise)
  --gray             one channel even when some camera is colour
  --quality Q        JPEG quality 1..100 (default 85)
  --wait S           how long the daemon waits for the next frame (default 5)

)") +
    connection_help();

}  // namespace

int snapshot_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"gray", "grey"}, {"output", "quality", "wait", "encoding"}, kSnapshotHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  const std::string output = args->required("output");
  const bool to_stdout = output == "-";
  if (args->has("encoding") && !to_stdout) {
    throw UsageError("--encoding is for -o -; a file's extension (.jpg, .png, .raw) chooses its encoding");
  }

  v1::SnapshotRequest request;
  request.set_view(args->positional()[0]);
  request.set_encoding(!to_stdout               ? encoding_for_path(output)
                       : args->has("encoding") ? encoding_from_name(args->get("encoding"), "--encoding")
                                               : v1::JPEG);
  if (request.encoding() == v1::H264) {
    throw UsageError("a snapshot is one still image: jpg, png or raw (h264 is for `omniview stream`)");
  }
  request.set_gray(args->has("gray") || args->has("grey"));
  if (args->has("quality")) {
    const int quality = parse_count(args->get("quality"), "--quality");
    if (quality > 100) throw UsageError("--quality: expected 1..100");
    request.set_quality(quality);
  }
  double wait_s = 5;
  if (args->has("wait")) wait_s = parse_positive(args->get("wait"), "--wait");
  request.set_timeout_ms(static_cast<int>(wait_s * 1000));

  Connection connection(connection_options(*args));
  v1::Frame frame;
  grpc::ClientContext context;
  connection.prepare(context, true);
  // The daemon may wait `wait_s` for a frame; give the call that long on top of --timeout.
  context.set_deadline(std::chrono::system_clock::now() + connection.options().deadline +
                       std::chrono::milliseconds(static_cast<int64_t>(wait_s * 1000)));
  connection.check(connection.stub().GetSnapshot(&context, request, &frame), view_label(request.view()));
  if (to_stdout) {
    const std::string& data = frame.data();
    if (std::fwrite(data.data(), 1, data.size(), stdout) != data.size() || std::fflush(stdout) != 0) {
      throw std::runtime_error("cannot write the frame to stdout");
    }
  } else {
    write_frame(output, frame);
  }
  (to_stdout ? std::cerr : std::cout) << (to_stdout ? "stdout" : output) << ": " << describe_frame(frame) << ", sequence " << frame.sequence() << ", captured "
            << format_time(frame.capture_time()) << "\n";
  return 0;
}

}  // namespace omniview::cli
