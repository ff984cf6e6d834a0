#include "server/web/stream/frame_message.h"

#include <google/protobuf/field_mask.pb.h>
#include <google/protobuf/util/field_mask_util.h>

#include "server/web/json/json.h"

namespace omniview::web {

namespace {

void put_u32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

// Every top-level field but `data`: copying through this mask leaves the image or point
// bytes where they are (fields added to the message later are included by themselves).
google::protobuf::FieldMask header_mask(const google::protobuf::Descriptor* d) {
  google::protobuf::FieldMask m;
  for (int i = 0; i < d->field_count(); ++i) {
    if (d->field(i)->name() != "data") m.add_paths(d->field(i)->name());
  }
  return m;
}

OutMessage with_data(uint32_t channel, const google::protobuf::Message& message, std::shared_ptr<const void> keep,
                     std::string_view data) {
  OutMessage m;
  m.binary = true;
  const std::string header = header_json(message);
  put_u32(m.head, channel);
  put_u32(m.head, static_cast<uint32_t>(header.size()));
  m.head += header;
  m.keep = std::move(keep);
  m.body = data;
  return m;
}

}  // namespace

std::string header_json(const google::protobuf::Message& message) {
  static const auto frame_mask = header_mask(v1::Frame::descriptor());
  static const auto cloud_mask = header_mask(v1::PointCloud::descriptor());
  const auto* d = message.GetDescriptor();
  std::unique_ptr<google::protobuf::Message> header(message.New());
  google::protobuf::util::FieldMaskUtil::MergeMessageTo(
      message, d == v1::Frame::descriptor() ? frame_mask : d == v1::PointCloud::descriptor() ? cloud_mask : header_mask(d),
      {}, header.get());
  return json::message_to_text(*header);
}

OutMessage frame_message(uint32_t channel, const SharedFrame& frame) {
  return with_data(channel, *frame, frame, frame->data());
}

OutMessage cloud_message(uint32_t channel, const std::shared_ptr<const v1::PointCloud>& cloud) {
  return with_data(channel, *cloud, cloud, cloud->data());
}

}  // namespace omniview::web
