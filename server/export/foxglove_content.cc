#include "server/export/foxglove_content.h"

#include <cmath>
#include <cstring>
#include <set>

#include "core/cloud/colourer.h"
#include "core/view/pinhole_view.h"
#include "foxglove/omniview_schemas.pb.h"
#include "server/web/foxglove/foxglove_fields.h"
#include "omniview/joint_states.pb.h"

namespace omniview::export_mcap {

namespace {

google::protobuf::Timestamp stamp(uint64_t ns) {
  google::protobuf::Timestamp t;
  t.set_seconds(static_cast<int64_t>(ns / 1000000000ull));
  t.set_nanos(static_cast<int32_t>(ns % 1000000000ull));
  return t;
}

using foxglove_fields::set_pinhole;

void add_transform(foxglove::FrameTransforms& out, uint64_t ns, const std::string& parent, const std::string& child,
                   const Pose& T) {
  foxglove_fields::add_transform(out, stamp(ns), parent, child, T.translation(), Eigen::Quaterniond(T.rotation()));
}

}  // namespace

uint64_t to_ns(std::chrono::system_clock::time_point t) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
  return ns > 0 ? static_cast<uint64_t>(ns) : 0;
}

std::string camera_calibration(const Camera& camera, uint64_t time_ns) {
  const ModelSpec spec = describe(camera.model);
  if (spec.camera_model != "pinhole" || spec.intrinsics.size() != 4) return "";
  foxglove::CameraCalibration c;
  *c.mutable_timestamp() = stamp(time_ns);
  c.set_frame_id(camera.name);
  c.set_width(static_cast<uint32_t>(camera.width));
  c.set_height(static_cast<uint32_t>(camera.height));
  if (spec.distortion_model == "radtan" || spec.distortion_model == "none") {
    c.set_distortion_model("plumb_bob");  // k1 k2 p1 p2 k3, as kalibr's radtan (+ k3)
    std::vector<double> d = spec.distortion;
    d.resize(5, 0.0);
    for (double v : d) c.add_d(v);
  } else if (spec.distortion_model == "equidistant") {
    c.set_distortion_model("kannala_brandt");  // k1 k2 k3 k4
    std::vector<double> d = spec.distortion;
    d.resize(4, 0.0);
    for (double v : d) c.add_d(v);
  } else {
    return "";
  }
  const auto& k = spec.intrinsics;  // fu fv pu pv
  set_pinhole(c, k[0], k[1], k[2], k[3]);
  return c.SerializeAsString();
}

std::string view_calibration(const View& view, const std::string& frame_id, uint64_t time_ns) {
  const auto* p = dynamic_cast<const PinholeView*>(&view);
  if (!p) return "";
  foxglove::CameraCalibration c;
  *c.mutable_timestamp() = stamp(time_ns);
  c.set_frame_id(frame_id);
  c.set_width(static_cast<uint32_t>(view.width()));
  c.set_height(static_cast<uint32_t>(view.height()));
  c.set_distortion_model("plumb_bob");  // a virtual camera has none: all five zero
  for (int i = 0; i < 5; ++i) c.add_d(0);
  set_pinhole(c, p->focal(), p->focal(), p->cx(), p->cy());
  return c.SerializeAsString();
}

std::string compressed_image(const std::string& frame_id, uint64_t time_ns, const std::string& format,
                             std::string_view data) {
  foxglove::CompressedImage m;
  *m.mutable_timestamp() = stamp(time_ns);
  m.set_frame_id(frame_id);
  m.set_format(format);
  m.set_data(std::string(data));
  return m.SerializeAsString();
}

std::string compressed_video(const std::string& frame_id, uint64_t time_ns, std::string_view data) {
  foxglove::CompressedVideo m;
  *m.mutable_timestamp() = stamp(time_ns);
  m.set_frame_id(frame_id);
  m.set_format("h264");
  m.set_data(std::string(data));
  return m.SerializeAsString();
}

std::string view_frame(const std::string& view) { return "view/" + view; }

std::string view_optical_frame(const std::string& view) { return "view/" + view + "/optical"; }

std::string frame_transforms(const Rig& rig, const std::vector<PosedView>& views, uint64_t time_ns) {
  foxglove::FrameTransforms out;
  for (const auto& frame : rig.frames().frames()) {
    const auto parent = rig.frames().parent_of(frame);
    if (!parent) continue;
    add_transform(out, time_ns, *parent, frame, rig.frames().lookup(*parent, frame));
  }
  Pose T_view_optical = Pose::Identity();
  T_view_optical.linear() = R_view_optical();
  for (const auto& v : views) {
    add_transform(out, time_ns, rig.default_frame(), view_frame(v.name), v.T_robot_view);
    add_transform(out, time_ns, view_frame(v.name), view_optical_frame(v.name), T_view_optical);
  }
  return out.SerializeAsString();
}

std::string point_cloud(const PointCloud& cloud, uint64_t time_ns) {
  foxglove::PointCloud out;
  *out.mutable_timestamp() = stamp(time_ns);
  out.set_frame_id(cloud.frame);
  out.mutable_pose()->mutable_position();
  out.mutable_pose()->mutable_orientation()->set_w(1);
  using F = foxglove::PackedElementField;
  const bool has_rgb = cloud.rgb.size() == cloud.size();
  const bool has_intensity = cloud.intensity.size() == cloud.size();
  uint32_t offset = 0;
  auto field = [&](const char* name, F::NumericType type, uint32_t size) {
    auto* f = out.add_fields();
    f->set_name(name);
    f->set_offset(offset);
    f->set_type(type);
    offset += size;
  };
  field("x", F::FLOAT32, 4);
  field("y", F::FLOAT32, 4);
  field("z", F::FLOAT32, 4);
  if (has_rgb) {
    // Foxglove's 3D panel colours from fields named red, green, blue, alpha.
    field("red", F::UINT8, 1);
    field("green", F::UINT8, 1);
    field("blue", F::UINT8, 1);
    field("alpha", F::UINT8, 1);
  }
  if (has_intensity) field("intensity", F::FLOAT32, 4);
  const uint32_t stride = offset;
  out.set_point_stride(stride);
  std::string data;
  data.reserve(cloud.size() * stride);
  char point[32];
  for (size_t i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3f& p = cloud.points[i];
    if (!p.allFinite()) continue;
    std::memcpy(point, p.data(), 12);
    size_t n = 12;
    if (has_rgb) {
      point[n++] = static_cast<char>(cloud.rgb[i][0]);
      point[n++] = static_cast<char>(cloud.rgb[i][1]);
      point[n++] = static_cast<char>(cloud.rgb[i][2]);
      point[n++] = static_cast<char>(255);
    }
    if (has_intensity) {
      std::memcpy(point + n, &cloud.intensity[i], 4);
      n += 4;
    }
    data.append(point, n);
  }
  out.set_data(std::move(data));
  return out.SerializeAsString();
}

std::string joint_states(const std::map<std::string, double>& joints, uint64_t time_ns) {
  omniview::JointStates m;
  *m.mutable_timestamp() = stamp(time_ns);
  for (const auto& [name, position] : joints) {
    m.add_name(name);
    m.add_position(position);
  }
  return m.SerializeAsString();
}

}  // namespace omniview::export_mcap
