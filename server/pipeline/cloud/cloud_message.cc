#include "server/pipeline/cloud/cloud_message.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include <google/protobuf/util/time_util.h>

namespace omniview {
namespace {

static_assert(std::endian::native == std::endian::little, "the packed layout is little-endian, as this host");

struct VoxelKey {
  int64_t x, y, z;
  bool operator==(const VoxelKey&) const = default;
};

struct VoxelKeyHash {
  size_t operator()(const VoxelKey& k) const {
    // Large primes spread neighbouring cells over the table.
    return static_cast<size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
  }
};

struct VoxelSum {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  size_t points = 0;
  Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
  size_t coloured = 0;
  uint8_t camera = kNoCamera;  // of the first coloured point
  uint8_t flags = 0;           // every point's flags, or'ed
};

PointCloud voxelise(const PointCloud& in, double size) {
  std::unordered_map<VoxelKey, size_t, VoxelKeyHash> index;
  std::vector<VoxelSum> sums;
  index.reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    const Eigen::Vector3d p = in.points[i].cast<double>();
    const VoxelKey key{static_cast<int64_t>(std::floor(p.x() / size)), static_cast<int64_t>(std::floor(p.y() / size)),
                       static_cast<int64_t>(std::floor(p.z() / size))};
    const auto [it, added] = index.try_emplace(key, sums.size());
    if (added) sums.emplace_back();
    VoxelSum& s = sums[it->second];
    s.position += p;
    ++s.points;
    s.flags |= in.flags[i];
    if (in.flags[i] & cloud_flags::kColoured) {
      s.rgb += Eigen::Vector3d(in.rgb[i][0], in.rgb[i][1], in.rgb[i][2]);
      if (s.coloured++ == 0) s.camera = in.camera[i];
    }
  }
  PointCloud out;
  out.frame = in.frame;
  out.stamp = in.stamp;
  for (const VoxelSum& s : sums) {
    out.points.push_back((s.position / static_cast<double>(s.points)).cast<float>());
    if (s.coloured > 0) {
      const Eigen::Vector3d c = s.rgb / static_cast<double>(s.coloured);
      out.rgb.push_back({static_cast<uint8_t>(std::lround(c.x())), static_cast<uint8_t>(std::lround(c.y())),
                         static_cast<uint8_t>(std::lround(c.z()))});
      out.flags.push_back(cloud_flags::kColoured);
    } else {
      out.rgb.push_back({0, 0, 0});
      out.flags.push_back(s.flags & cloud_flags::kSelf ? cloud_flags::kSelf : s.flags & cloud_flags::kOccluded);
    }
    out.camera.push_back(s.camera);
  }
  return out;
}

void put_field(v1::PointCloud& m, const char* name, uint32_t offset, v1::PointField::DataType type) {
  auto* f = m.add_fields();
  f->set_name(name);
  f->set_offset(offset);
  f->set_datatype(type);
  f->set_count(1);
}

}  // namespace

PointCloud shape_cloud(const PointCloud& coloured, const CloudShape& shape) {
  coloured.check("coloured cloud");
  const size_t n = coloured.size();
  PointCloud out;
  out.frame = shape.frame;
  out.stamp = coloured.stamp;
  out.points.reserve(n);
  out.rgb.reserve(n);
  out.flags.reserve(n);
  out.camera.reserve(n);
  const Eigen::Isometry3f T = shape.T_out_cloud.cast<float>();
  for (size_t i = 0; i < n; ++i) {
    if (!coloured.points[i].allFinite()) continue;
    const Eigen::Vector3f p = T * coloured.points[i];
    if (shape.crop && !shape.crop->contains(p.cast<double>())) continue;
    out.points.push_back(p);
    out.rgb.push_back(coloured.rgb.empty() ? PointCloud::Rgb{0, 0, 0} : coloured.rgb[i]);
    out.flags.push_back(coloured.flags.empty() ? 0 : coloured.flags[i]);
    out.camera.push_back(coloured.camera.empty() ? kNoCamera : coloured.camera[i]);
  }
  return shape.voxel_m > 0 ? voxelise(out, shape.voxel_m) : out;
}

v1::PointCloud pack_cloud(const PointCloud& cloud) {
  cloud.check("packed cloud");
  v1::PointCloud m;
  m.set_frame(cloud.frame);
  *m.mutable_stamp() = google::protobuf::util::TimeUtil::NanosecondsToTimestamp(
      std::chrono::duration_cast<std::chrono::nanoseconds>(cloud.stamp.time_since_epoch()).count());
  put_field(m, "x", 0, v1::PointField::FLOAT32);
  put_field(m, "y", 4, v1::PointField::FLOAT32);
  put_field(m, "z", 8, v1::PointField::FLOAT32);
  put_field(m, "r", 12, v1::PointField::UINT8);
  put_field(m, "g", 13, v1::PointField::UINT8);
  put_field(m, "b", 14, v1::PointField::UINT8);
  put_field(m, "flags", 15, v1::PointField::UINT8);
  put_field(m, "camera", 16, v1::PointField::UINT8);
  m.set_point_stride(kPackedPointStride);
  m.set_point_count(static_cast<uint32_t>(cloud.size()));
  std::string data(cloud.size() * kPackedPointStride, '\0');
  v1::CloudCounts& counts = *m.mutable_counts();
  for (size_t i = 0; i < cloud.size(); ++i) {
    char* p = data.data() + i * kPackedPointStride;
    std::memcpy(p, cloud.points[i].data(), 12);
    const uint8_t flags = cloud.flags.empty() ? 0 : cloud.flags[i];
    const PointCloud::Rgb rgb = cloud.rgb.empty() ? PointCloud::Rgb{0, 0, 0} : cloud.rgb[i];
    p[12] = static_cast<char>(rgb[0]);
    p[13] = static_cast<char>(rgb[1]);
    p[14] = static_cast<char>(rgb[2]);
    p[15] = static_cast<char>(flags);
    p[16] = static_cast<char>(cloud.camera.empty() ? kNoCamera : cloud.camera[i]);
    if (flags & cloud_flags::kColoured) {
      counts.set_coloured(counts.coloured() + 1);
    } else if (flags & cloud_flags::kSelf) {
      counts.set_self_filtered(counts.self_filtered() + 1);
    } else if (flags & cloud_flags::kOccluded) {
      counts.set_occluded(counts.occluded() + 1);
    } else {
      counts.set_unseen(counts.unseen() + 1);
    }
  }
  counts.set_points(cloud.size());
  m.set_data(std::move(data));
  return m;
}

}  // namespace omniview
