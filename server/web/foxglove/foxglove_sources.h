// What feeds each kind of Foxglove topic to a subscription's Pump: a view's frames as
// images, video or its calibration, a source's clouds, and the /tf clock.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "server/pipeline/pipeline.h"
#include "server/web/json/json.h"
#include "server/web/stream/pump.h"

namespace omniview::web::foxglove_io {

enum class Topic { kImage, kVideo, kCalibration, kCloud, kTransforms };

// A view's frame as the message of `topic` (kImage, kVideo or kCalibration) for `subscription`.
std::function<OutMessage(const SharedFrame&)> frame_data(uint32_t subscription, Topic topic, std::string frame_id);
// A coloured cloud as a foxglove.PointCloud for `subscription`.
OutMessage cloud_data(uint32_t subscription, const SharedCloud& cloud);
// /tf: a FrameTransforms message at once, then once a second, from the pipeline's frames tree.
Pump::Source transforms_source(uint32_t subscription, Pipeline& pipeline);

// The error status a subscription that ended on its own (its view deleted, the daemon
// stopping) sends: "<topic>: <why>".
template <class AnySubscriber>
std::function<void(const AnySubscriber&)> ended_status(std::weak_ptr<Connection> connection, std::string topic) {
  return [connection = std::move(connection), topic = std::move(topic)](const AnySubscriber& subscriber) {
    if (const auto c = connection.lock()) {
      c->send_text("{\"op\":\"status\",\"level\":2,\"message\":" + json::quote(topic + ": " + subscriber.close_reason()) +
                   "}");
    }
  };
}

}  // namespace omniview::web::foxglove_io
