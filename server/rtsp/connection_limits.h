// How many RTSP connections are open, in all and per client address, against the config's
// caps: a connection beyond either is refused at accept, before it can ask for a media
// (each media is a GStreamer pipeline with threads of its own). Thread-safe; made with
// std::make_shared (its slots keep it).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace omniview {

class ConnectionLimits : public std::enable_shared_from_this<ConnectionLimits> {
 public:
  ConnectionLimits(int max_connections, int max_per_client)
      : max_connections_(max_connections), max_per_client_(max_per_client) {}

  // Held for as long as a connection is open; the slot is freed when it is destroyed.
  class Slot {
   public:
    Slot(std::shared_ptr<ConnectionLimits> limits, std::string host)
        : limits_(std::move(limits)), host_(std::move(host)) {}
    ~Slot() { limits_->release(host_); }
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

   private:
    const std::shared_ptr<ConnectionLimits> limits_;  // a client may outlive the server by a moment
    const std::string host_;
  };

  // A slot for a connection from `host`, or nullptr and why (for the log) when a cap is
  // reached.
  std::unique_ptr<Slot> acquire(const std::string& host, std::string* why = nullptr);
  int open() const;

 private:
  void release(const std::string& host);

  const int max_connections_;
  const int max_per_client_;
  mutable std::mutex mutex_;
  int open_ = 0;
  std::map<std::string, int> per_host_;
};

}  // namespace omniview
