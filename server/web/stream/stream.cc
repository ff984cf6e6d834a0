#include "server/web/stream/stream.h"

namespace omniview::web {

Stream::Stream(std::weak_ptr<Connection> connection, uint32_t channel, Pump::Source source,
               std::function<void()> release)
    : release_(std::move(release)) {
  // An end the client asked for is no news to it: only ends of the subscriber's own are told.
  if (source.ended) {
    source.ended = [stopping = stopping_, ended = std::move(source.ended)] {
      if (!*stopping) ended();
    };
  }
  pump_ = std::make_unique<Pump>(std::move(connection), channel, std::move(source));
}

Stream::~Stream() { stop(); }

void Stream::stop() {
  if (stopping_->exchange(true)) return;
  pump_->stop();
  if (release_) release_();
}

}  // namespace omniview::web
