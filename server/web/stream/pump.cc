#include "server/web/stream/pump.h"

namespace omniview::web {

namespace {
constexpr auto kPoll = std::chrono::milliseconds(100);  // how often a waiting take() checks for stop
}

Pump::Pump(std::weak_ptr<Connection> connection, uint32_t channel, Source source)
    : connection_(std::move(connection)), channel_(channel), source_(std::move(source)) {
  thread_ = std::thread([this] { run(); });
}

Pump::~Pump() { stop(); }

void Pump::stop() {
  {
    std::lock_guard lock(state_->mutex);
    state_->stop = true;
  }
  state_->changed.notify_all();
  if (source_.interrupt) source_.interrupt();
  if (thread_.joinable()) {
    // A pump that ends itself (its view deleted) may be stopped from its own thread.
    if (thread_.get_id() == std::this_thread::get_id()) {
      thread_.detach();
    } else {
      thread_.join();
    }
  }
}

void Pump::run() {
  while (true) {
    {
      std::lock_guard lock(state_->mutex);
      if (state_->stop) return;
    }
    Item item = source_.take(kPoll);
    if (item.kind == Item::kNothing) continue;
    if (item.kind == Item::kEnd) {
      if (source_.ended) source_.ended();
      return;
    }
    const auto connection = connection_.lock();
    if (!connection) return;
    {
      std::lock_guard lock(state_->mutex);
      if (state_->stop) return;
      state_->in_flight = true;
    }
    connection->send_latest(channel_, std::move(item.message), [state = state_](bool written) {
      {
        std::lock_guard lock(state->mutex);
        state->in_flight = false;
        state->written = written;
      }
      state->changed.notify_all();
    });
    std::unique_lock lock(state_->mutex);
    state_->changed.wait(lock, [&] { return !state_->in_flight || state_->stop; });
    if (state_->stop) return;
    const bool written = state_->written;
    lock.unlock();
    if (written && source_.sent) source_.sent();
  }
}

}  // namespace omniview::web
