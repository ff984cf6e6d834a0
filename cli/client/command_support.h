// What the client commands share: argument parsing with --help, tables, time stamps, and
// stopping a stream cleanly on Ctrl-C or after a duration.
#pragma once

#include <google/protobuf/timestamp.pb.h>
#include <grpcpp/client_context.h>

#include "omniview/v1/omniview.pb.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "cli/args.h"
#include "core/io/quote.h"

namespace omniview::cli {

// Parses `argv` of a client command: -o and -h stand for --output and --help, `switches`
// take no value, and any flag outside `flags`, `switches` and the connection flags is an
// error. Returns nullopt after printing `help` when --help was given.
std::optional<Args> parse_command_args(const std::vector<std::string>& argv, const std::vector<std::string>& switches,
                                       const std::vector<std::string>& flags, const std::string& help);

// Exactly `n` positional arguments, named in the error by `names` ("VIEW").
void expect_positional(const Args& args, size_t n, const std::string& names);

double parse_positive(const std::string& text, const std::string& what);  // a number > 0
int parse_count(const std::string& text, const std::string& what);        // an integer >= 1

// Columns padded to their widest cell.
class Table {
 public:
  explicit Table(std::vector<std::string> header) { rows_.push_back(std::move(header)); }
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print(std::ostream& out, const std::string& indent = "") const;

 private:
  std::vector<std::vector<std::string>> rows_;
};

std::string fixed(double value, int decimals);

// "view 'NAME'" for messages, with at most a short prefix of a name the user typed (a
// 20 000-character name echoed whole buries the daemon's own, short, error).
inline std::string view_label(const std::string& name) { return "view " + quote_prefix(name); }
// "2026-11-22T18:40:01.123Z"
std::string format_time(const google::protobuf::Timestamp& t);
double to_seconds(const google::protobuf::Timestamp& t);
double now_seconds();  // since the Unix epoch, for latencies against capture times

// Prints the daemon's note on a stream (say, a --rate above its limit that it capped) to
// stderr as "note: ...". Call once the first frame arrived (the metadata came with it).
void print_stream_note(const grpc::ClientContext& context);

// Below this fraction of its pixels seen by some camera, a view is mostly black: `status`
// and `watch` say so (coverage comes with every frame and in the status).
inline constexpr double kLowCoverage = 0.5;
// "view 'left' shows only 38 % of its pixels from the cameras; the rest is black: ..."
// for a coverage below kLowCoverage, else "".
std::string low_coverage_warning(const std::string& view, double coverage);

// Says on stderr when a view's frames turn stale (its source delivers nothing new; the
// daemon re-sends the last picture about once a second, Frame.stale) and when they are
// live again. Stale frames are not new images: commands neither count nor write them.
class StaleNotice {
 public:
  explicit StaleNotice(std::string view) : view_(std::move(view)) {}
  // Returns frame.stale(); prints on a change (and when the reason changes).
  bool check(const v1::Frame& frame);

 private:
  std::string view_;
  bool stale_ = false;
  std::string gist_;  // the reason without its count of seconds
};

// Cancels a streaming call when the user presses Ctrl-C, when `duration_s` (> 0) has
// passed, or on stop(), so a command can end cleanly and print its summary. A second
// Ctrl-C kills the process as usual.
class StreamStopper {
 public:
  StreamStopper(grpc::ClientContext& context, double duration_s);
  ~StreamStopper();
  StreamStopper(const StreamStopper&) = delete;
  StreamStopper& operator=(const StreamStopper&) = delete;

  void stop();
  // True once the call was cancelled on purpose (its CANCELLED status is no error).
  bool stopped() const { return stopped_; }
  bool interrupted() const;  // by Ctrl-C

 private:
  void run(double duration_s);
  grpc::ClientContext& context_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::atomic<bool> stopped_{false};
  std::thread thread_;
};

}  // namespace omniview::cli
