#include "cli/client/cloud_decode.h"

#include <cstring>
#include <map>
#include <stdexcept>

#include <google/protobuf/util/time_util.h>

namespace omniview::cli {
namespace {

size_t datatype_size(v1::PointField::DataType t) {
  switch (t) {
    case v1::PointField::INT8:
    case v1::PointField::UINT8:
      return 1;
    case v1::PointField::INT16:
    case v1::PointField::UINT16:
      return 2;
    case v1::PointField::INT32:
    case v1::PointField::UINT32:
    case v1::PointField::FLOAT32:
      return 4;
    case v1::PointField::FLOAT64:
      return 8;
    default:
      return 0;
  }
}

// One value of a field as a double (the little-endian host reads the bytes as they are).
double read_value(const char* at, v1::PointField::DataType t) {
  switch (t) {
    case v1::PointField::INT8: return static_cast<int8_t>(*at);
    case v1::PointField::UINT8: return static_cast<uint8_t>(*at);
    case v1::PointField::INT16: { int16_t v; std::memcpy(&v, at, 2); return v; }
    case v1::PointField::UINT16: { uint16_t v; std::memcpy(&v, at, 2); return v; }
    case v1::PointField::INT32: { int32_t v; std::memcpy(&v, at, 4); return v; }
    case v1::PointField::UINT32: { uint32_t v; std::memcpy(&v, at, 4); return v; }
    case v1::PointField::FLOAT32: { float v; std::memcpy(&v, at, 4); return v; }
    case v1::PointField::FLOAT64: { double v; std::memcpy(&v, at, 8); return v; }
    default: return 0;
  }
}

}  // namespace

PointCloud cloud_from_message(const v1::PointCloud& m) {
  const size_t n = m.point_count(), stride = m.point_stride();
  if (m.data().size() != n * stride) {
    throw std::runtime_error("cloud message: " + std::to_string(m.data().size()) + " bytes of data for " +
                             std::to_string(n) + " points of " + std::to_string(stride) + " bytes");
  }
  std::map<std::string, const v1::PointField*> fields;
  for (const auto& f : m.fields()) {
    const size_t size = datatype_size(f.datatype());
    if (size == 0) throw std::runtime_error("cloud message: field '" + f.name() + "' has an unknown datatype");
    if (f.count() < 1 || f.offset() + size * f.count() > stride) {
      throw std::runtime_error("cloud message: field '" + f.name() + "' does not fit in a point of " +
                               std::to_string(stride) + " bytes");
    }
    fields[f.name()] = &f;
  }
  for (const char* required : {"x", "y", "z"}) {
    if (!fields.count(required)) throw std::runtime_error(std::string("cloud message: no field '") + required + "'");
  }
  PointCloud cloud;
  cloud.frame = m.frame();
  cloud.stamp = std::chrono::system_clock::time_point(std::chrono::duration_cast<std::chrono::system_clock::duration>(
      std::chrono::nanoseconds(google::protobuf::util::TimeUtil::TimestampToNanoseconds(m.stamp()))));
  const bool colour = fields.count("r") && fields.count("g") && fields.count("b");
  cloud.points.resize(n);
  if (colour) cloud.rgb.resize(n);
  if (fields.count("flags")) cloud.flags.resize(n);
  if (fields.count("camera")) cloud.camera.resize(n);
  const auto value = [&](size_t i, const char* name) {
    const v1::PointField& f = *fields.at(name);
    return read_value(m.data().data() + i * stride + f.offset(), f.datatype());
  };
  for (size_t i = 0; i < n; ++i) {
    cloud.points[i] = Eigen::Vector3f(static_cast<float>(value(i, "x")), static_cast<float>(value(i, "y")),
                                      static_cast<float>(value(i, "z")));
    if (colour) {
      cloud.rgb[i] = {static_cast<uint8_t>(value(i, "r")), static_cast<uint8_t>(value(i, "g")),
                      static_cast<uint8_t>(value(i, "b"))};
    }
    if (!cloud.flags.empty()) cloud.flags[i] = static_cast<uint8_t>(value(i, "flags"));
    if (!cloud.camera.empty()) cloud.camera[i] = static_cast<uint8_t>(value(i, "camera"));
  }
  return cloud;
}

}  // namespace omniview::cli
