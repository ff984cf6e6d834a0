#include "server/web/foxglove/foxglove_messages.h"

#include <chrono>
#include <cstring>
#include <set>

#include <Eigen/Geometry>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include "core/rig/rig.h"
#include "server/web/foxglove/foxglove_fields.h"
#include "server/web/foxglove/foxglove_schema.h"

namespace omniview::web::foxglove_io {

namespace pb = google::protobuf;

namespace {

std::string base64(const std::string& in) {
  static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
    for (int s = 18; s >= 0; s -= 6) out += kAlphabet[(v >> s) & 63];
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint8_t(in[i]) << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == in.size()) {
    const uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

void put_le(std::string& out, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((v >> (8 * i)) & 0xff);
}

void put_varint(std::string& out, uint64_t v) {
  while (v >= 0x80) {
    out += static_cast<char>((v & 0x7f) | 0x80);
    v >>= 7;
  }
  out += static_cast<char>(v);
}

pb::Timestamp now_timestamp() {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  pb::Timestamp t;
  t.set_seconds(ns / 1000000000);
  t.set_nanos(static_cast<int32_t>(ns % 1000000000));
  return t;
}

using foxglove_fields::add_transform;

foxglove::PackedElementField::NumericType numeric_type(v1::PointField::DataType t) {
  using F = foxglove::PackedElementField;
  switch (t) {
    case v1::PointField::INT8: return F::INT8;
    case v1::PointField::UINT8: return F::UINT8;
    case v1::PointField::INT16: return F::INT16;
    case v1::PointField::UINT16: return F::UINT16;
    case v1::PointField::INT32: return F::INT32;
    case v1::PointField::UINT32: return F::UINT32;
    case v1::PointField::FLOAT32: return F::FLOAT32;
    case v1::PointField::FLOAT64: return F::FLOAT64;
    default: return F::UNKNOWN;
  }
}

}  // namespace

uint64_t time_ns(const pb::Timestamp& t) {
  return static_cast<uint64_t>(t.seconds()) * 1000000000ULL + static_cast<uint64_t>(t.nanos());
}

std::string schema_base64(const pb::Descriptor* message_type) {
  return base64(foxglove_schema::descriptor_set(message_type));
}

OutMessage message_data(uint32_t subscription, uint64_t time, const std::string& prefix, int data_field,
                        std::string_view data, std::shared_ptr<const void> keep) {
  OutMessage m;
  m.binary = true;
  m.head.reserve(13 + prefix.size() + 12);
  m.head += static_cast<char>(0x01);  // messageData
  put_le(m.head, subscription, 4);
  put_le(m.head, time, 8);
  m.head += prefix;
  if (data_field > 0) {
    put_varint(m.head, (static_cast<uint64_t>(data_field) << 3) | 2);  // length-delimited
    put_varint(m.head, data.size());
    m.body = data;
    m.keep = std::move(keep);
  }
  return m;
}

std::string compressed_image_prefix(const v1::Frame& frame, const std::string& frame_id) {
  foxglove::CompressedImage image;
  *image.mutable_timestamp() = frame.capture_time();
  image.set_frame_id(frame_id);
  image.set_format(frame.encoding() == v1::PNG ? "png" : "jpeg");
  return image.SerializeAsString();
}

std::string compressed_video_prefix(const v1::Frame& frame, const std::string& frame_id) {
  foxglove::CompressedVideo video;
  *video.mutable_timestamp() = frame.capture_time();
  video.set_frame_id(frame_id);
  video.set_format("h264");
  return video.SerializeAsString();
}

std::string camera_calibration(const v1::Frame& frame, const std::string& frame_id) {
  const auto& k = frame.camera().intrinsics();
  if (k.size() != 4) return "";
  const double fx = k[0], fy = k[1], cx = k[2], cy = k[3];
  foxglove::CameraCalibration c;
  *c.mutable_timestamp() = frame.capture_time();
  c.set_frame_id(frame_id);
  c.set_width(static_cast<uint32_t>(frame.width()));
  c.set_height(static_cast<uint32_t>(frame.height()));
  c.set_distortion_model("plumb_bob");  // a virtual camera has none: all five zero
  for (int i = 0; i < 5; ++i) c.add_d(0);
  foxglove_fields::set_pinhole(c, fx, fy, cx, cy);
  return c.SerializeAsString();
}

std::string point_cloud_prefix(const v1::PointCloud& cloud) {
  foxglove::PointCloud out;
  *out.mutable_timestamp() = cloud.stamp();
  out.set_frame_id(cloud.frame());
  out.mutable_pose()->mutable_orientation()->set_w(1);
  out.mutable_pose()->mutable_position();
  out.set_point_stride(cloud.point_stride());
  for (const auto& f : cloud.fields()) {
    // Foxglove's fields are single values: a field of `count` n becomes n fields.
    const int size = f.datatype() == v1::PointField::FLOAT64                                     ? 8
                     : f.datatype() == v1::PointField::FLOAT32 || f.datatype() == v1::PointField::INT32 ||
                             f.datatype() == v1::PointField::UINT32                               ? 4
                     : f.datatype() == v1::PointField::INT16 || f.datatype() == v1::PointField::UINT16 ? 2
                                                                                                  : 1;
    const uint32_t count = std::max<uint32_t>(1, f.count());
    // Foxglove's colour fields by the names its 3D panel looks for.
    const std::string name = f.name() == "r"   ? "red"
                             : f.name() == "g" ? "green"
                             : f.name() == "b" ? "blue"
                                               : f.name();
    for (uint32_t i = 0; i < count; ++i) {
      auto* field = out.add_fields();
      field->set_name(count == 1 ? name : name + std::to_string(i));
      field->set_offset(f.offset() + i * size);
      field->set_type(numeric_type(f.datatype()));
    }
  }
  // Its "RGBA (separate fields)" colour mode wants all four: alpha is the byte appended.
  auto* alpha = out.add_fields();
  alpha->set_name("alpha");
  alpha->set_offset(cloud.point_stride());
  alpha->set_type(foxglove::PackedElementField::UINT8);
  out.set_point_stride(cloud.point_stride() + 1);
  return out.SerializeAsString();
}

std::string foxglove_points(const v1::PointCloud& cloud) {
  const size_t stride = cloud.point_stride();
  const size_t n = stride ? cloud.data().size() / stride : 0;
  std::string out(n * (stride + 1), static_cast<char>(0xff));
  for (size_t i = 0; i < n; ++i) std::memcpy(out.data() + i * (stride + 1), cloud.data().data() + i * stride, stride);
  return out;
}

std::string view_frame(const std::string& view) { return "view/" + view; }

std::string view_optical_frame(const std::string& view) { return "view/" + view + "/optical"; }

std::string frame_transforms(Pipeline& pipeline) {
  foxglove::FrameTransforms out;
  const pb::Timestamp stamp = now_timestamp();
  std::set<std::string> done;  // a frame has one parent, whichever source names it first
  for (const auto& source : pipeline.report().sources) {
    std::shared_ptr<const Rig> rig;
    try {
      rig = pipeline.rig(source.name);
    } catch (const std::exception&) {
      continue;
    }
    if (!rig) continue;
    for (const auto& frame : rig->frames().frames()) {
      const auto parent = rig->frames().parent_of(frame);
      if (!parent || !done.insert(frame).second) continue;
      const Pose T = rig->frames().lookup(*parent, frame);
      add_transform(out, stamp, *parent, frame, T.translation(), Eigen::Quaterniond(T.rotation()));
    }
  }
  // The view frame (x along the view, y left, z up) and its optical frame (x right, y
  // down, z along the view), which the view's images and calibration name.
  Eigen::Matrix3d R_view_optical;
  R_view_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const Eigen::Quaterniond q_optical(R_view_optical);
  for (const auto& view : pipeline.list_views()) {
    const std::string frame = view_frame(view.spec().name());
    if (!done.insert(frame).second) continue;
    const auto& p = view.pose();
    const double norm = p.qw() * p.qw() + p.qx() * p.qx() + p.qy() * p.qy() + p.qz() * p.qz();
    if (view.robot_frame().empty() || !(norm > 0)) continue;  // not posed yet
    add_transform(out, stamp, view.robot_frame(), frame,
                  {p.translation().x(), p.translation().y(), p.translation().z()},
                  Eigen::Quaterniond(p.qw(), p.qx(), p.qy(), p.qz()).normalized());
    add_transform(out, stamp, frame, view_optical_frame(view.spec().name()), Eigen::Vector3d::Zero(), q_optical);
  }
  return out.SerializeAsString();
}

}  // namespace omniview::web::foxglove_io
