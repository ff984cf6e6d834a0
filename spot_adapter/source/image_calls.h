// GetImage calls in flight, answered in the order they were made.
//
// One call at a time caps the image rate at one set per round trip: 3 Hz over Wi-Fi with a
// 300 ms round trip, far below the cameras' 15 Hz. With calls overlapping (a new one every
// 1/rate_hz while older ones are still out, up to a limit) the rate is limit / round trip,
// and the image sets still reach the views in capture order.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include <grpcpp/grpcpp.h>

#include "bosdyn/api/image_service.grpc.pb.h"

namespace omniview::spot {

struct ImageCall {
  grpc::ClientContext context;
  std::shared_ptr<bosdyn::api::ImageService::Stub> stub;  // kept until the call ends
  bosdyn::api::GetImageRequest request;
  bosdyn::api::GetImageResponse response;
  std::vector<size_t> wanted;  // the slots asked for, in request order
  std::vector<size_t> depth;   // the slots whose depth was asked for after them
  grpc::Status status;
  bool done = false;  // guarded by ImageCalls' mutex until the call is taken
};

class ImageCalls {
 public:
  ImageCalls() = default;
  ~ImageCalls() { cancel_all(); }
  ImageCalls(const ImageCalls&) = delete;
  ImageCalls& operator=(const ImageCalls&) = delete;

  size_t in_flight() const;

  // Sends `call` (its context already prepared: deadline, metadata).
  void start(std::unique_ptr<ImageCall> call);

  // The oldest call once it is answered, or null at `deadline` or after interrupt().
  std::unique_ptr<ImageCall> wait_oldest(std::chrono::steady_clock::time_point deadline);

  // Cancels every call and waits for gRPC to finish each (their memory is in use until then).
  void cancel_all();

  // Makes wait_oldest() return now, and at once from then on (the source is stopping).
  void interrupt();

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::unique_ptr<ImageCall>> calls_;
  bool interrupted_ = false;
};

}  // namespace omniview::spot
