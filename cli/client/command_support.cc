#include "cli/client/command_support.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "cli/client/connection.h"

namespace omniview::cli {
namespace {

volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_interrupt(int) {
  g_interrupted = 1;
  std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C ends the process at once
}

}  // namespace

std::optional<Args> parse_command_args(const std::vector<std::string>& argv, const std::vector<std::string>& switches,
                                       const std::vector<std::string>& flags, const std::string& help) {
  std::vector<std::string> expanded;
  for (const auto& a : argv) expanded.push_back(a == "-o" ? "--output" : a == "-h" ? "--help" : a);
  std::vector<std::string> all_switches = switches;
  all_switches.push_back("help");
  std::vector<std::string> known = flags;
  known.insert(known.end(), all_switches.begin(), all_switches.end());
  known.insert(known.end(), connection_flags().begin(), connection_flags().end());
  if (std::find(expanded.begin(), expanded.end(), "--help") != expanded.end()) {
    std::cout << help;
    return std::nullopt;
  }
  // Before Args sees them: an unknown flag would otherwise swallow the next word as its value.
  for (const auto& a : expanded) {
    if (a.rfind("--", 0) != 0 || a == "--") continue;
    const std::string name = a.substr(2, a.find('=') - 2);
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      throw UsageError("unknown option --" + name + " (see --help)");
    }
  }
  Args args(expanded, all_switches);
  for (const auto& p : args.positional()) {
    if (p.size() > 1 && p[0] == '-' && p != "--" && !std::isdigit(static_cast<unsigned char>(p[1]))) {
      throw UsageError("unknown option " + p + " (see --help)");
    }
  }
  return args;
}

void expect_positional(const Args& args, size_t n, const std::string& names) {
  if (args.positional().size() < n) throw UsageError("missing " + names);
  if (args.positional().size() > n) throw UsageError("unexpected argument '" + args.positional()[n] + "'");
}

double parse_positive(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !(v > 0) || !std::isfinite(v)) {
    throw UsageError(what + ": expected a number > 0, got '" + text + "'");
  }
  return v;
}

int parse_count(const std::string& text, const std::string& what) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || v < 1 || v > 1000000000) {
    throw UsageError(what + ": expected a whole number >= 1, got '" + text + "'");
  }
  return static_cast<int>(v);
}

void Table::print(std::ostream& out, const std::string& indent) const {
  std::vector<size_t> widths;
  for (const auto& row : rows_) {
    widths.resize(std::max(widths.size(), row.size()));
    for (size_t i = 0; i < row.size(); ++i) widths[i] = std::max(widths[i], row[i].size());
  }
  for (const auto& row : rows_) {
    std::string line = indent;
    for (size_t i = 0; i < row.size(); ++i) {
      line += row[i];
      if (i + 1 < row.size()) line += std::string(widths[i] - row[i].size() + 2, ' ');
    }
    out << line << "\n";
  }
}

std::string fixed(double value, int decimals) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << value;
  return s.str();
}

std::string format_time(const google::protobuf::Timestamp& t) {
  if (t.seconds() == 0 && t.nanos() == 0) return "-";
  const std::time_t seconds = t.seconds();
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  std::ostringstream s;
  s << std::put_time(&utc, "%Y-%m-%dT%H:%M:%S") << '.' << std::setw(3) << std::setfill('0') << t.nanos() / 1000000
    << 'Z';
  return s.str();
}

double to_seconds(const google::protobuf::Timestamp& t) { return t.seconds() + t.nanos() * 1e-9; }

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

void print_stream_note(const grpc::ClientContext& context) {
  const auto& metadata = context.GetServerInitialMetadata();
  const auto [begin, end] = metadata.equal_range("omniview-note");
  for (auto it = begin; it != end; ++it) std::cerr << "note: " << std::string(it->second.data(), it->second.size()) << "\n";
}

StreamStopper::StreamStopper(grpc::ClientContext& context, double duration_s) : context_(context) {
  g_interrupted = 0;
  std::signal(SIGINT, on_interrupt);
  thread_ = std::thread([this, duration_s] { run(duration_s); });
}

StreamStopper::~StreamStopper() {
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  wake_.notify_all();
  thread_.join();
  std::signal(SIGINT, SIG_DFL);
}

void StreamStopper::stop() {
  stopped_ = true;
  context_.TryCancel();
}

bool StreamStopper::interrupted() const { return g_interrupted != 0; }

void StreamStopper::run(double duration_s) {
  // A signal handler may only set a flag; this thread turns the flag into a cancel.
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock lock(mutex_);
  while (!done_) {
    wake_.wait_for(lock, std::chrono::milliseconds(50));
    const bool timed_out =
        duration_s > 0 && std::chrono::steady_clock::now() - start >= std::chrono::duration<double>(duration_s);
    if (!stopped_ && (g_interrupted || timed_out)) stop();
  }
}

bool StaleNotice::check(const v1::Frame& frame) {
  if (!frame.stale()) {
    if (stale_) std::cerr << "omniview: view '" << view_ << "' is live again\n" << std::flush;
    stale_ = false;
    return false;
  }
  // The reason counts seconds ("... for 4.2 s: it is not connected"): say it again only
  // when what follows the count changes.
  const std::string& reason = frame.stale_reason();
  const size_t count_end = reason.find(" s", reason.find(" for "));
  const std::string gist = count_end == std::string::npos ? reason : reason.substr(count_end + 2);
  if (!stale_ || gist != gist_) {
    std::cerr << "omniview: view '" << view_ << "' is stale, showing its last picture: " << reason << "\n"
              << std::flush;
  }
  stale_ = true;
  gist_ = gist;
  return true;
}

std::string low_coverage_warning(const std::string& view, double coverage) {
  if (coverage >= kLowCoverage) return "";
  return "view '" + view + "' shows only " + fixed(coverage * 100, 0) +
         " % of its pixels from the cameras; the rest is black: point it where the cameras look "
         "('omniview cameras' lists their poses and fields of view)";
}

}  // namespace omniview::cli
