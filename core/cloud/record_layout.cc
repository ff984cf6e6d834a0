#include "core/cloud/record_layout.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>

namespace omniview::cloud_io {

size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::kI8: case Scalar::kU8: return 1;
    case Scalar::kI16: case Scalar::kU16: return 2;
    case Scalar::kI32: case Scalar::kU32: case Scalar::kF32: return 4;
    default: return 8;
  }
}

bool scalar_is_float(Scalar s) { return s == Scalar::kF32 || s == Scalar::kF64; }

Slot slot_for_name(std::string_view n) {
  if (n == "x") return Slot::kX;
  if (n == "y") return Slot::kY;
  if (n == "z") return Slot::kZ;
  if (n == "red" || n == "r" || n == "diffuse_red") return Slot::kR;
  if (n == "green" || n == "g" || n == "diffuse_green") return Slot::kG;
  if (n == "blue" || n == "b" || n == "diffuse_blue") return Slot::kB;
  if (n == "rgb" || n == "rgba") return Slot::kPackedRgb;
  if (n == "intensity" || n == "scalar_intensity" || n == "i") return Slot::kIntensity;
  if (n == "time" || n == "t" || n == "timestamp") return Slot::kTime;
  if (n == "ring") return Slot::kRing;
  if (n == "flags") return Slot::kFlags;
  if (n == "camera") return Slot::kCamera;
  return Slot::kIgnored;
}

double read_scalar(const uint8_t* p, Scalar s, bool big_endian, uint64_t* bits) {
  uint8_t b[8];
  const size_t n = scalar_size(s);
  std::memcpy(b, p, n);
  const bool host_big = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;
  if (big_endian != host_big) std::reverse(b, b + n);
  uint64_t raw = 0;
  double value = 0;
  switch (s) {
    case Scalar::kI8: { int8_t v; std::memcpy(&v, b, 1); value = v; raw = static_cast<uint8_t>(v); break; }
    case Scalar::kU8: { uint8_t v; std::memcpy(&v, b, 1); value = v; raw = v; break; }
    case Scalar::kI16: { int16_t v; std::memcpy(&v, b, 2); value = v; raw = static_cast<uint16_t>(v); break; }
    case Scalar::kU16: { uint16_t v; std::memcpy(&v, b, 2); value = v; raw = v; break; }
    case Scalar::kI32: { int32_t v; std::memcpy(&v, b, 4); value = v; raw = static_cast<uint32_t>(v); break; }
    case Scalar::kU32: { uint32_t v; std::memcpy(&v, b, 4); value = v; raw = v; break; }
    case Scalar::kI64: { int64_t v; std::memcpy(&v, b, 8); value = static_cast<double>(v); raw = static_cast<uint64_t>(v); break; }
    case Scalar::kU64: { uint64_t v; std::memcpy(&v, b, 8); value = static_cast<double>(v); raw = v; break; }
    case Scalar::kF32: { float v; std::memcpy(&v, b, 4); value = v; uint32_t r; std::memcpy(&r, b, 4); raw = r; break; }
    case Scalar::kF64: { double v; std::memcpy(&v, b, 8); value = v; std::memcpy(&raw, b, 8); break; }
  }
  if (bits) *bits = raw;
  return value;
}

bool parse_scalar(std::string_view token, Scalar s, double& value, uint64_t& bits) {
  if (token.empty()) return false;
  const char* first = token.data();
  const char* last = first + token.size();
  if (scalar_is_float(s)) {
    // strtod accepts nan/inf as PCL writes them; it needs a terminated string.
    const std::string text(token);
    char* end = nullptr;
    value = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size()) return false;
    if (s == Scalar::kF32) {
      const float f = static_cast<float>(value);
      uint32_t r;
      std::memcpy(&r, &f, 4);
      bits = r;
    } else {
      std::memcpy(&bits, &value, 8);
    }
    return true;
  }
  if (*first == '+') ++first;
  const bool is_signed = s == Scalar::kI8 || s == Scalar::kI16 || s == Scalar::kI32 || s == Scalar::kI64;
  if (is_signed) {
    int64_t v = 0;
    const auto r = std::from_chars(first, last, v);
    if (r.ec != std::errc() || r.ptr != last) return false;
    value = static_cast<double>(v);
    bits = static_cast<uint64_t>(v);
  } else {
    uint64_t v = 0;
    const auto r = std::from_chars(first, last, v);
    if (r.ec != std::errc() || r.ptr != last) return false;
    value = static_cast<double>(v);
    bits = v;
  }
  // Out of range for its declared type: report rather than wrap.
  const size_t n = scalar_size(s);
  if (n < 8) {
    const double hi = is_signed ? std::ldexp(1.0, int(8 * n) - 1) - 1 : std::ldexp(1.0, int(8 * n)) - 1;
    const double lo = is_signed ? -std::ldexp(1.0, int(8 * n) - 1) : 0;
    if (value < lo || value > hi) return false;
    bits &= (uint64_t{1} << (8 * n)) - 1;
  }
  return true;
}

CloudAssembler::CloudAssembler(const std::vector<Field>& fields, const std::string& what)
    : fields_(fields), what_(what) {
  bool x = false, y = false, z = false;
  for (auto& f : fields_) {
    f.slot = slot_for_name(f.name);
    record_size_ += scalar_size(f.type) * f.count;
    value_count_ += f.count;
    switch (f.slot) {
      case Slot::kX: x = true; break;
      case Slot::kY: y = true; break;
      case Slot::kZ: z = true; break;
      case Slot::kR: case Slot::kG: case Slot::kB: case Slot::kPackedRgb: has_rgb_ = true; break;
      case Slot::kIntensity: has_intensity_ = true; break;
      case Slot::kTime: has_time_ = true; break;
      case Slot::kRing: has_ring_ = true; break;
      case Slot::kFlags: has_flags_ = true; break;
      case Slot::kCamera: has_camera_ = true; break;
      default: break;
    }
  }
  std::string missing;
  if (!x) missing += " x";
  if (!y) missing += " y";
  if (!z) missing += " z";
  if (!missing.empty()) throw CloudFormatError(what_ + ": no point field(s)" + missing);
}

void CloudAssembler::begin(PointCloud& cloud, size_t points, size_t max_reserve) const {
  const size_t n = std::min(points, max_reserve);
  cloud.points.reserve(n);
  if (has_rgb_) cloud.rgb.reserve(n);
  if (has_intensity_) cloud.intensity.reserve(n);
  if (has_time_) cloud.time.reserve(n);
  if (has_ring_) cloud.ring.reserve(n);
  if (has_flags_) cloud.flags.reserve(n);
  if (has_camera_) cloud.camera.reserve(n);
}

namespace {

uint8_t colour_byte(double v, Scalar type) {
  // Float colours are in [0, 1] (PCL, Open3D); integer ones in [0, 255].
  if (scalar_is_float(type)) v *= 255.0;
  if (!(v > 0)) return 0;
  if (v >= 255) return 255;
  return static_cast<uint8_t>(std::lround(v));
}

}  // namespace

void CloudAssembler::put(PointCloud& cloud, size_t i, const Field& f, double value, uint64_t bits) const {
  switch (f.slot) {
    case Slot::kX: cloud.points[i].x() = static_cast<float>(value); break;
    case Slot::kY: cloud.points[i].y() = static_cast<float>(value); break;
    case Slot::kZ: cloud.points[i].z() = static_cast<float>(value); break;
    case Slot::kR: cloud.rgb[i][0] = colour_byte(value, f.type); break;
    case Slot::kG: cloud.rgb[i][1] = colour_byte(value, f.type); break;
    case Slot::kB: cloud.rgb[i][2] = colour_byte(value, f.type); break;
    case Slot::kPackedRgb:  // PCL packs 0x00RRGGBB into the bits of a float or uint32
      cloud.rgb[i] = {static_cast<uint8_t>(bits >> 16), static_cast<uint8_t>(bits >> 8), static_cast<uint8_t>(bits)};
      break;
    case Slot::kIntensity: cloud.intensity[i] = static_cast<float>(value); break;
    case Slot::kTime: cloud.time[i] = static_cast<float>(value); break;
    case Slot::kRing:
      cloud.ring[i] = value >= 0 && value <= 65535 ? static_cast<uint16_t>(value) : uint16_t{0};
      break;
    case Slot::kFlags: cloud.flags[i] = static_cast<uint8_t>(bits); break;
    case Slot::kCamera: cloud.camera[i] = value >= 0 && value < 255 ? static_cast<uint8_t>(value) : kNoCamera; break;
    default: break;
  }
}

namespace {

void grow(PointCloud& cloud, bool rgb, bool intensity, bool time, bool ring, bool flags, bool camera) {
  cloud.points.emplace_back(0.f, 0.f, 0.f);
  if (rgb) cloud.rgb.push_back({0, 0, 0});
  if (intensity) cloud.intensity.push_back(0.f);
  if (time) cloud.time.push_back(0.f);
  if (ring) cloud.ring.push_back(0);
  if (flags) cloud.flags.push_back(0);
  if (camera) cloud.camera.push_back(kNoCamera);
}

}  // namespace

void CloudAssembler::add_binary(PointCloud& cloud, const uint8_t* p, bool big_endian) const {
  const size_t i = cloud.points.size();
  grow(cloud, has_rgb_, has_intensity_, has_time_, has_ring_, has_flags_, has_camera_);
  for (const auto& f : fields_) {
    if (f.slot != Slot::kIgnored) {
      uint64_t bits = 0;
      const double v = read_scalar(p, f.type, big_endian, &bits);
      put(cloud, i, f, v, bits);
    }
    p += scalar_size(f.type) * f.count;
  }
}

void CloudAssembler::add_values(PointCloud& cloud, const double* values, const uint64_t* bits) const {
  const size_t i = cloud.points.size();
  grow(cloud, has_rgb_, has_intensity_, has_time_, has_ring_, has_flags_, has_camera_);
  for (const auto& f : fields_) {
    if (f.slot != Slot::kIgnored) put(cloud, i, f, *values, *bits);
    values += f.count;
    bits += f.count;
  }
}

std::string stamp_to_string(std::chrono::system_clock::time_point stamp) {
  return std::to_string(std::chrono::duration_cast<std::chrono::nanoseconds>(stamp.time_since_epoch()).count());
}

bool stamp_from_string(std::string_view text, std::chrono::system_clock::time_point& stamp) {
  int64_t ns = 0;
  const auto r = std::from_chars(text.data(), text.data() + text.size(), ns);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size()) return false;
  stamp = std::chrono::system_clock::time_point(
      std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::nanoseconds(ns)));
  return true;
}

void fail(const std::string& name, const std::string& message) {
  throw CloudFormatError(name + ": " + message);
}

void check_point_limit(uint64_t declared, size_t max_points, const std::string& name) {
  if (declared > max_points) {
    fail(name, "its header declares " + std::to_string(declared) + " points, more than the limit of " +
                   std::to_string(max_points));
  }
}

}  // namespace omniview::cloud_io
