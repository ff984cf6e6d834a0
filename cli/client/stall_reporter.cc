#include "cli/client/stall_reporter.h"

#include <cmath>

namespace omniview::cli {
namespace {

using Clock = std::chrono::steady_clock;

int64_t now_ns() { return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count(); }

}  // namespace

StallReporter::StallReporter(Connection& connection, std::string view, Print print, std::chrono::milliseconds quiet)
    : connection_(connection), view_(std::move(view)), print_(std::move(print)), quiet_(quiet), last_frame_ns_(now_ns()) {
  thread_ = std::thread([this] { run(); });
}

StallReporter::~StallReporter() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void StallReporter::frame_arrived() { last_frame_ns_ = now_ns(); }

void StallReporter::run() {
  std::unique_lock lock(mutex_);
  while (!wake_.wait_for(lock, std::chrono::seconds(1), [&] { return stopping_; })) {
    const double quiet_s = (now_ns() - last_frame_ns_.load()) / 1e9;
    if (quiet_s * 1000 < static_cast<double>(quiet_.count())) continue;
    lock.unlock();
    const std::string reason = why();
    lock.lock();
    if (stopping_) break;
    print_("no frames for " + std::to_string(static_cast<int>(std::floor(quiet_s))) + " s: " + reason);
  }
}

std::string StallReporter::why() const {
  grpc::ClientContext view_context, status_context;
  connection_.prepare(view_context, true);
  connection_.prepare(status_context, true);
  v1::GetViewRequest get;
  get.set_name(view_);
  v1::View view;
  v1::Status status;
  if (!connection_.stub().GetView(&view_context, get, &view).ok() ||
      !connection_.stub().GetStatus(&status_context, v1::GetStatusRequest(), &status).ok()) {
    return "the daemon does not answer";
  }
  for (const auto& s : status.sources()) {
    if (s.name() != view.spec().source()) continue;
    if (!s.connected()) return "source '" + s.name() + "' is not connected: " + s.message();
    if (s.last_frame_age_s() > 2) {
      return "source '" + s.name() + "' delivered nothing for " + std::to_string(static_cast<int>(s.last_frame_age_s())) +
             " s" + (s.message().empty() ? "" : ": " + s.message());
    }
    return "source '" + s.name() + "' is delivering; the view's cameras may not be in its images" +
           (s.message().empty() ? "" : " (" + s.message() + ")");
  }
  return "the view's source is not in the daemon's status";
}

}  // namespace omniview::cli
