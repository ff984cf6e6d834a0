#include "server/web/ws/outbox.h"

namespace omniview::web {

bool Outbox::push_text(std::string text) {
  if (text_bytes_ + text.size() > max_text_bytes_) return false;
  text_bytes_ += text.size();
  texts_.push_back(std::move(text));
  return true;
}

void Outbox::push_latest(uint32_t channel, OutMessage message, std::function<void(bool)> done) {
  auto [it, inserted] = latest_.try_emplace(channel);
  if (!inserted && it->second.done) it->second.done(false);  // replaced unsent: newest wins
  it->second = Next{std::move(message), std::move(done)};
}

std::optional<Outbox::Next> Outbox::pop() {
  if (!texts_.empty()) {
    Next next;
    next.message.head = std::move(texts_.front());
    texts_.pop_front();
    text_bytes_ -= next.message.head.size();
    return next;
  }
  if (latest_.empty()) return std::nullopt;
  auto it = latest_.upper_bound(last_channel_);
  if (it == latest_.end()) it = latest_.begin();
  last_channel_ = it->first;
  Next next = std::move(it->second);
  latest_.erase(it);
  return next;
}

void Outbox::drop_all() {
  texts_.clear();
  text_bytes_ = 0;
  drop_channels();
}

void Outbox::drop_channels() {
  auto waiting = std::move(latest_);
  latest_.clear();
  for (auto& [channel, next] : waiting) {
    if (next.done) next.done(false);
  }
}

}  // namespace omniview::web
