// A view's frame as the console receives it: one binary WebSocket message,
//   uint32 LE channel | uint32 LE header length | header (the Frame without `data`, JSON) | data
// where data is the encoded image, sent from the pipeline's shared buffer (never copied or
// re-encoded per client).
#pragma once

#include <cstdint>
#include <string>

#include "server/pipeline/subscriber.h"
#include "server/web/ws/connection.h"

namespace omniview::web {

OutMessage frame_message(uint32_t channel, const SharedFrame& frame);
// A coloured cloud the same way: the PointCloud without `data` as the header, then its
// packed points (docs/API.md, "Point clouds").
OutMessage cloud_message(uint32_t channel, const std::shared_ptr<const v1::PointCloud>& cloud);
// Every field of `message` but its `data`, as proto3 JSON.
std::string header_json(const google::protobuf::Message& message);

}  // namespace omniview::web
