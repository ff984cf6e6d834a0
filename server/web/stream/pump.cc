#include "server/web/stream/pump.h"

#include <iostream>

#include "server/pipeline/subscription.h"

namespace omniview::web {

Pump::Pump(std::weak_ptr<Connection> connection, uint32_t channel, Source source) {
  core_->connection = std::move(connection);
  core_->channel = channel;
  core_->source = std::move(source);
  thread_ = std::thread([core = core_] {
    // An exception here (a message that could not be made) ends this client's connection,
    // never the daemon.
    try {
      run(core);
    } catch (const std::exception& e) {
      fail(core, e.what());
    } catch (...) {
      fail(core, "an exception of unknown type");
    }
  });
}

Pump::~Pump() { stop(); }

void Pump::stop() {
  {
    std::lock_guard lock(core_->mutex);
    core_->stop = true;
  }
  core_->changed.notify_all();
  if (core_->source.interrupt) core_->source.interrupt();
  if (thread_.joinable()) {
    // Stopped from its own thread (see Core): it exits at its next check of `stop`.
    if (thread_.get_id() == std::this_thread::get_id()) {
      thread_.detach();
    } else {
      thread_.join();
    }
  }
}

void Pump::fail(const std::shared_ptr<Core>& core, const std::string& why) {
  const auto connection = core->connection.lock();
  if (!connection) return;
  std::cerr << "omniviewd: web: " << connection->peer() << ": internal error on channel " << core->channel << ": "
            << why << ": connection closed" << std::endl;
  connection->close(1011, "internal server error");
}

void Pump::run(const std::shared_ptr<Core>& core) {
  while (true) {
    {
      std::lock_guard lock(core->mutex);
      if (core->stop) return;
    }
    Item item = core->source.take(kFrontEndPoll);
    if (item.kind == Item::kNothing) continue;
    if (item.kind == Item::kEnd) {
      if (core->source.ended) core->source.ended();
      return;
    }
    {
      const auto connection = core->connection.lock();
      if (!connection) return;
      // As late as it can be: a frame of a view that changed since it was taken is dropped.
      if (item.admit && !item.admit()) continue;
      {
        std::lock_guard lock(core->mutex);
        if (core->stop) return;
        core->in_flight = true;
      }
      connection->send_latest(core->channel, std::move(item.message), [core](bool written) {
        {
          std::lock_guard lock(core->mutex);
          core->in_flight = false;
          core->written = written;
        }
        core->changed.notify_all();
      });
    }  // may have been the connection's last owner: this Pump may be gone now, `core` is not
    std::unique_lock lock(core->mutex);
    core->changed.wait(lock, [&] { return !core->in_flight || core->stop; });
    if (core->stop) return;
    const bool written = core->written;
    lock.unlock();
    if (written && core->source.sent) core->source.sent();
  }
}

}  // namespace omniview::web
