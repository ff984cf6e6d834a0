// `omniview watch VIEW`: a live line of frame rate, latency, size and drops.
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <mutex>

#include "cli/client/client_commands.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "cli/client/frame_files.h"
#include "cli/client/stall_reporter.h"

namespace omniview::cli {
namespace {

const std::string kWatchHelp = std::string(R"(usage: omniview watch VIEW [--duration S] [--encoding E] [--rate HZ] [--gray]

Streams a view and prints, once a second, what arrives: frames per second, latency
(the daemon's, from the images' arrival to the frame's encoding: median and max over the
second), age (capture time to arrival here: needs synchronised clocks), frame size, and
skipped source frames (gaps in the sequence numbers: frames of the source this client did
not get, whether left out by --rate, by a view slower than its source, or dropped from its
slot because it read too slowly; 'omniview status' counts only the last, as DROPPED).
Ctrl-C stops; the summary is printed however the stream ends.

  --duration S       stop after S seconds
)") + stream_help() + "\n" +
                          connection_help();

// Frames seen in the current one-second window.
struct Window {
  int frames = 0;
  uint64_t skipped = 0;
  std::vector<double> latencies_ms, ages_ms;
  void clear() { *this = Window(); }
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

std::string summary_of_skips(uint64_t skipped, bool rate_limited) {
  return std::to_string(skipped) + " source frames skipped" + (rate_limited && skipped > 0 ? " (most by --rate)" : "");
}

std::string line(const std::string& view, const Window& w, double seconds, const v1::Frame& last,
                 uint64_t skipped_total) {
  const double max_latency =
      w.latencies_ms.empty() ? 0 : *std::max_element(w.latencies_ms.begin(), w.latencies_ms.end());
  return view + "  " + fixed(w.frames / seconds, 1) + " fps  latency p50 " + fixed(median(w.latencies_ms), 1) +
         " max " + fixed(max_latency, 1) + " ms  age p50 " +
         (w.ages_ms.empty() ? std::string("-") : fixed(median(w.ages_ms), 1) + " ms") + "  " + describe_frame(last) +
         "  skipped " + std::to_string(w.skipped) + " (total " + std::to_string(skipped_total) + ")  rev " +
         std::to_string(last.camera().revision());
}

}  // namespace

int watch_command(const std::vector<std::string>& argv) {
  std::vector<std::string> flags = stream_flags();
  flags.push_back("duration");
  const auto args = parse_command_args(argv, stream_switches(), flags, kWatchHelp);
  if (!args) return 0;
  expect_positional(*args, 1, "VIEW");
  const double duration_s = args->has("duration") ? parse_positive(args->get("duration"), "--duration") : 0;
  const auto request = stream_request(*args, args->positional()[0], v1::JPEG);

  Connection connection(connection_options(*args));
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, duration_s);
  auto reader = connection.stub().StreamFrames(&context, request);

  // On a terminal the line is rewritten in place; in a log, one line a second.
  const bool tty = isatty(STDOUT_FILENO);
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto window_start = start;
  Window window;
  v1::Frame frame, last;
  uint64_t frames_total = 0, skipped_total = 0, last_sequence = 0;
  std::mutex output;  // the stall reporter prints from its own thread
  const auto print = [&](const std::string& text) {
    std::lock_guard lock(output);
    std::cout << (tty ? "\r\033[K" + text : text + "\n") << std::flush;
  };
  StallReporter stall(connection, request.view(), print);
  StaleNotice stale(request.view());
  while (reader->Read(&frame)) {
    stall.frame_arrived();
    if (stale.check(frame)) {  // the last picture again: not a frame, but a line a second
      print(request.view() + "  STALE: " + frame.stale_reason());
      window.clear();
      window_start = Clock::now();
      continue;
    }
    const double arrival_s = now_seconds();
    if (frames_total > 0 && frame.sequence() > last_sequence + 1) {
      window.skipped += frame.sequence() - last_sequence - 1;
      skipped_total += frame.sequence() - last_sequence - 1;
    }
    last_sequence = frame.sequence();
    if (frames_total == 0 || frame.camera().revision() != last.camera().revision()) {
      if (frames_total == 0) print_stream_note(context);
      // Once per view revision: a ptz step can turn a view toward what no camera sees.
      const std::string warning = low_coverage_warning(request.view(), frame.coverage());
      if (!warning.empty()) {
        std::lock_guard lock(output);
        std::cerr << (tty ? "\r\033[K" : "") << "warning: " << warning << "\n" << std::flush;
      }
    }
    ++frames_total;
    ++window.frames;
    window.latencies_ms.push_back(frame.latency_ms());
    if (frame.has_capture_time()) window.ages_ms.push_back((arrival_s - to_seconds(frame.capture_time())) * 1000);
    last = std::move(frame);
    const double seconds = std::chrono::duration<double>(Clock::now() - window_start).count();
    if (seconds >= 1) {
      print(line(request.view(), window, seconds, last, skipped_total));
      window.clear();
      window_start = Clock::now();
    }
  }
  const grpc::Status status = reader->Finish();
  if (tty && frames_total > 0) std::cout << "\n";
  const bool failed = !status.ok() && !(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED);
  // The summary also when the stream failed (daemon shutting down, view deleted), then why.
  if (frames_total > 0 || !failed) {
    const double total_s = std::chrono::duration<double>(Clock::now() - start).count();
    std::cout << frames_total << " frames in " << fixed(total_s, 1) << " s (" << fixed(frames_total / total_s, 1)
              << " fps), " << summary_of_skips(skipped_total, request.max_rate_hz() > 0) << "\n"
              << std::flush;
  }
  if (failed) connection.check(status, view_label(request.view()));
  return 0;
}

}  // namespace omniview::cli
