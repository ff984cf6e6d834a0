// `omniview snapshot VIEW -o FILE`: the next frame of a view, saved as the server encodes it.
#include <iostream>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/frame_files.h"

namespace omniview::cli {
namespace {

const std::string kHelp =
    std::string(R"(usage: omniview snapshot VIEW -o OUT.png|OUT.jpg|OUT.raw [--gray] [--quality Q] [--wait S]

Saves the next frame of a view. The extension chooses the encoding; .raw is the pixels
as they are (rows top to bottom, 8-bit RGB or gray; the size is printed).

  -o, --output FILE  where to write
  --gray             one channel even when some camera is colour
  --quality Q        JPEG quality 1..100 (default 85)
  --wait S           how long the daemon waits for the next frame (default 5)

)") +
    connection_help();

}  // namespace

int snapshot_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"gray", "grey"}, {"output", "quality", "wait"}, kHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  const std::string output = args->required("output");

  v1::SnapshotRequest request;
  request.set_view(args->positional()[0]);
  request.set_encoding(encoding_for_path(output));
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
  connection.check(connection.stub().GetSnapshot(&context, request, &frame), "view '" + request.view() + "'");
  write_frame(output, frame);
  std::cout << output << ": " << describe_frame(frame) << ", sequence " << frame.sequence() << ", captured "
            << format_time(frame.capture_time()) << "\n";
  return 0;
}

}  // namespace omniview::cli
