#include "spot_adapter/source/image_calls.h"

namespace omniview::spot {

size_t ImageCalls::in_flight() const {
  std::lock_guard lock(mutex_);
  return calls_.size();
}

void ImageCalls::start(std::unique_ptr<ImageCall> call) {
  ImageCall* c = call.get();
  {
    std::lock_guard lock(mutex_);
    calls_.push_back(std::move(call));
  }
  // The callback runs on a gRPC thread, perhaps before GetImage() returns.
  c->stub->async()->GetImage(&c->context, &c->request, &c->response, [this, c](grpc::Status status) {
    std::lock_guard lock(mutex_);
    c->status = std::move(status);
    c->done = true;
    changed_.notify_all();
  });
}

std::unique_ptr<ImageCall> ImageCalls::wait_oldest(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock lock(mutex_);
  changed_.wait_until(lock, deadline, [&] { return interrupted_ || (!calls_.empty() && calls_.front()->done); });
  if (interrupted_ || calls_.empty() || !calls_.front()->done) return nullptr;
  auto call = std::move(calls_.front());
  calls_.pop_front();
  return call;
}

void ImageCalls::cancel_all() {
  std::unique_lock lock(mutex_);
  for (auto& c : calls_) {
    if (!c->done) c->context.TryCancel();
  }
  changed_.wait(lock, [&] {
    for (const auto& c : calls_) {
      if (!c->done) return false;
    }
    return true;
  });
  calls_.clear();
}

void ImageCalls::interrupt() {
  {
    std::lock_guard lock(mutex_);
    interrupted_ = true;
  }
  changed_.notify_all();
}

}  // namespace omniview::spot
