// omniview's frames, clouds and frames tree as Foxglove messages (proto/foxglove), and the
// schema a client decodes them with.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "foxglove/omniview_schemas.pb.h"
#include "server/pipeline/cloud/cloud_subscriber.h"
#include "server/pipeline/pipeline.h"
#include "server/web/ws/connection.h"

namespace omniview::web::foxglove_io {

// The base64 FileDescriptorSet of `message_type`'s file and everything it imports: the
// `schema` of a channel with schemaEncoding "protobuf".
std::string schema_base64(const google::protobuf::Descriptor* message_type);

// A messageData frame (opcode 1, subscription id, receive time in ns, payload) whose
// payload is `prefix` followed by the bytes field `data_field` holding `data` (not copied:
// `keep` holds it), so a frame's JPEG or a cloud's points go out from the pipeline's
// buffer. `prefix` is the message serialized without that field.
OutMessage message_data(uint32_t subscription, uint64_t time_ns, const std::string& prefix, int data_field,
                        std::string_view data, std::shared_ptr<const void> keep);

// The messages, as serialized payload prefixes (see message_data).
std::string compressed_image_prefix(const v1::Frame& frame, const std::string& frame_id);
// An H264 frame (one access unit) as a CompressedVideo prefix.
std::string compressed_video_prefix(const v1::Frame& frame, const std::string& frame_id);
// Empty when the view is not a pinhole camera (panoramas, fisheye).
std::string camera_calibration(const v1::Frame& frame, const std::string& frame_id);
// Foxglove colours points from fields named red, green, blue and alpha: the packed layout's
// r, g, b are renamed and an alpha byte (255) follows each point (foxglove_points).
std::string point_cloud_prefix(const v1::PointCloud& cloud);
std::string foxglove_points(const v1::PointCloud& cloud);

// A view's frame and its optical frame (which its images and calibration name). The "view/"
// prefix keeps them apart from the robot's frames (a view named `back` beside Spot's `back`),
// and view names hold no '/', so no view's frames collide with another's.
std::string view_frame(const std::string& view);
std::string view_optical_frame(const std::string& view);
// Every source's rig frames, every view's frame and its optical frame under it.
std::string frame_transforms(Pipeline& pipeline);

uint64_t time_ns(const google::protobuf::Timestamp& t);

}  // namespace omniview::web::foxglove_io
