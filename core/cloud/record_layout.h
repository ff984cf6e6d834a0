// The per-point record of a PLY or PCD file: named scalar fields of given types, read from
// binary (either byte order) or ASCII text, and the PointCloud field each one fills.
// Shared by the PLY and PCD readers so both interpret names and types the same way.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "core/cloud/point_cloud.h"

namespace omniview::cloud_io {

enum class Scalar { kI8, kU8, kI16, kU16, kI32, kU32, kI64, kU64, kF32, kF64 };

size_t scalar_size(Scalar s);
bool scalar_is_float(Scalar s);

// Where a field's value goes.
enum class Slot { kIgnored, kX, kY, kZ, kR, kG, kB, kPackedRgb, kIntensity, kTime, kRing, kFlags, kCamera };

// Slot for a field name as PLY, PCD, PCL, Open3D and CloudCompare write them.
Slot slot_for_name(std::string_view name);

struct Field {
  std::string name;
  Scalar type = Scalar::kF32;
  size_t count = 1;  // PCD COUNT; values beyond the first are ignored
  Slot slot = Slot::kIgnored;
};

// Fills a cloud one record at a time. `what` names the file for errors.
class CloudAssembler {
 public:
  CloudAssembler(const std::vector<Field>& fields, const std::string& what);
  // Checks that x, y and z are present; reserves within what `max_points` can justify.
  void begin(PointCloud& cloud, size_t points, size_t max_reserve) const;
  // Binary record at `p` (size record_size()).
  void add_binary(PointCloud& cloud, const uint8_t* p, bool big_endian) const;
  // ASCII record: one value per field entry (field.count of them), already split.
  void add_values(PointCloud& cloud, const double* values, const uint64_t* raw_bits) const;
  size_t record_size() const { return record_size_; }
  size_t value_count() const { return value_count_; }

 private:
  void put(PointCloud& cloud, size_t index, const Field& f, double value, uint64_t bits) const;
  std::vector<Field> fields_;
  std::string what_;
  size_t record_size_ = 0;
  size_t value_count_ = 0;
  bool has_rgb_ = false, has_intensity_ = false, has_time_ = false, has_ring_ = false, has_flags_ = false,
       has_camera_ = false;
};

// Reads a scalar from `p` as double and as its raw bits (for packed colours).
double read_scalar(const uint8_t* p, Scalar s, bool big_endian, uint64_t* bits = nullptr);

// Parses one ASCII number of type `s` (integers exactly; floats with strtod). False when
// `token` is not a number of that kind.
bool parse_scalar(std::string_view token, Scalar s, double& value, uint64_t& bits);

// Little-endian appenders for the writers.
template <typename T>
void put_le(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__) {
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  out.append(bytes, sizeof(T));
}

// Appends " <value>" (ASCII writers).
inline void append_word(std::string& out, uint64_t value) {
  out.push_back(' ');
  out += std::to_string(value);
}

// Stamp and frame as both writers record them in comments.
// Throws CloudFormatError "NAME: MESSAGE": the file (or source) first, as every reader says it.
[[noreturn]] void fail(const std::string& name, const std::string& message);
// Refuses a header that declares more than `max_points` points, before its body is read.
void check_point_limit(uint64_t declared, size_t max_points, const std::string& name);

std::string stamp_to_string(std::chrono::system_clock::time_point stamp);
bool stamp_from_string(std::string_view text, std::chrono::system_clock::time_point& stamp);

}  // namespace omniview::cloud_io
