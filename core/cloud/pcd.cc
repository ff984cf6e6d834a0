// PCD v0.7 (PCL's point cloud data): header lines VERSION, FIELDS, SIZE, TYPE, COUNT,
// WIDTH, HEIGHT, VIEWPOINT, POINTS, DATA, then ascii lines or packed binary records.
// DATA binary_compressed (LZF) is refused by name: convert such files with PCL's
// pcl_convert_pcd_ascii_binary.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "core/cloud/cloud_file.h"
#include "core/cloud/record_layout.h"
#include "core/cloud/text_cursor.h"

namespace omniview {
namespace {

using cloud_io::check_point_limit;
using cloud_io::fail;
using cloud_io::Field;
using cloud_io::Scalar;

std::optional<Scalar> pcd_type(char type, uint64_t size) {
  if (type == 'F') {
    if (size == 4) return Scalar::kF32;
    if (size == 8) return Scalar::kF64;
  } else if (type == 'I') {
    if (size == 1) return Scalar::kI8;
    if (size == 2) return Scalar::kI16;
    if (size == 4) return Scalar::kI32;
    if (size == 8) return Scalar::kI64;
  } else if (type == 'U') {
    if (size == 1) return Scalar::kU8;
    if (size == 2) return Scalar::kU16;
    if (size == 4) return Scalar::kU32;
    if (size == 8) return Scalar::kU64;
  }
  return std::nullopt;
}

uint64_t parse_count(std::string_view word, const std::string& name, const std::string& where) {
  double v = 0;
  uint64_t bits = 0;
  if (!cloud_io::parse_scalar(word, Scalar::kU64, v, bits)) fail(name, where + ": '" + std::string(word) + "' is not a count");
  return bits;
}

}  // namespace

PointCloud parse_pcd(std::string_view data, const std::string& name, size_t max_points) {
  cloud_io::TextCursor cur(data);
  std::vector<std::string> field_names;
  std::vector<uint64_t> sizes, counts;
  std::vector<char> types;
  std::optional<uint64_t> width, height, points;
  std::string data_kind;
  PointCloud cloud;
  std::map<std::string, size_t> seen;
  while (data_kind.empty()) {
    if (cur.at_end()) fail(name, "header ends before its DATA line");
    const size_t line_no = cur.line_number();
    const std::string_view line = cur.line();
    const std::string where = "header line " + std::to_string(line_no);
    std::vector<std::string_view> w;
    cloud_io::for_each_word(line, [&](std::string_view word) { w.push_back(word); });
    if (w.empty()) continue;
    if (w[0].front() == '#') {
      // Our own comments carry the frame and stamp: "# omniview frame base_link".
      if (w.size() >= 4 && w[0] == "#" && w[1] == "omniview") {
        if (w[2] == "frame") cloud.frame = std::string(w[3]);
        if (w[2] == "stamp_ns") cloud_io::stamp_from_string(w[3], cloud.stamp);
      }
      continue;
    }
    const std::string key(w[0]);
    if (++seen[key] > 1) fail(name, where + ": " + key + " appears twice");
    const std::vector<std::string_view> args(w.begin() + 1, w.end());
    if (key == "VERSION") {
      if (args.size() != 1 || (args[0] != "0.7" && args[0] != ".7")) fail(name, where + ": only PCD VERSION 0.7 is supported");
    } else if (key == "FIELDS") {
      for (auto a : args) field_names.emplace_back(a);
      if (field_names.empty()) fail(name, where + ": FIELDS names no field");
    } else if (key == "SIZE") {
      for (auto a : args) sizes.push_back(parse_count(a, name, where + " (SIZE)"));
    } else if (key == "TYPE") {
      for (auto a : args) {
        if (a.size() != 1) fail(name, where + ": TYPE '" + std::string(a) + "' is not one of I, U, F");
        types.push_back(a[0]);
      }
    } else if (key == "COUNT") {
      for (auto a : args) counts.push_back(parse_count(a, name, where + " (COUNT)"));
    } else if (key == "WIDTH") {
      if (args.size() != 1) fail(name, where + ": WIDTH takes one number");
      width = parse_count(args[0], name, where + " (WIDTH)");
    } else if (key == "HEIGHT") {
      if (args.size() != 1) fail(name, where + ": HEIGHT takes one number");
      height = parse_count(args[0], name, where + " (HEIGHT)");
    } else if (key == "VIEWPOINT") {
      if (args.size() != 7) fail(name, where + ": VIEWPOINT takes 7 numbers (tx ty tz qw qx qy qz)");
    } else if (key == "POINTS") {
      if (args.size() != 1) fail(name, where + ": POINTS takes one number");
      points = parse_count(args[0], name, where + " (POINTS)");
    } else if (key == "DATA") {
      if (args.size() != 1) fail(name, where + ": DATA takes one word");
      data_kind = std::string(args[0]);
      if (data_kind == "binary_compressed") {
        fail(name, "DATA binary_compressed is not supported; convert the file to binary or ascii "
                   "(e.g. pcl_convert_pcd_ascii_binary IN OUT 1)");
      }
      if (data_kind != "ascii" && data_kind != "binary") fail(name, where + ": unknown DATA kind '" + data_kind + "'");
    } else {
      fail(name, where + ": unknown header keyword '" + key + "'");
    }
  }
  const size_t n_fields = field_names.size();
  if (n_fields == 0) fail(name, "header has no FIELDS line");
  if (sizes.size() != n_fields) fail(name, "SIZE lists " + std::to_string(sizes.size()) + " sizes for " + std::to_string(n_fields) + " FIELDS");
  if (types.size() != n_fields) fail(name, "TYPE lists " + std::to_string(types.size()) + " types for " + std::to_string(n_fields) + " FIELDS");
  if (counts.empty()) counts.assign(n_fields, 1);  // COUNT is optional
  if (counts.size() != n_fields) fail(name, "COUNT lists " + std::to_string(counts.size()) + " counts for " + std::to_string(n_fields) + " FIELDS");
  std::vector<Field> fields;
  for (size_t i = 0; i < n_fields; ++i) {
    const auto type = pcd_type(types[i], sizes[i]);
    if (!type) {
      fail(name, "field '" + field_names[i] + "': TYPE " + std::string(1, types[i]) + " with SIZE " + std::to_string(sizes[i]) +
                     " is not a valid pair");
    }
    if (counts[i] == 0 || counts[i] > 4096) fail(name, "field '" + field_names[i] + "': COUNT " + std::to_string(counts[i]) + " out of 1..4096");
    fields.push_back({field_names[i], *type, static_cast<size_t>(counts[i]), cloud_io::Slot::kIgnored});
  }
  if (!points) {
    if (!width || !height) fail(name, "header has neither POINTS nor WIDTH and HEIGHT");
    if (*height != 0 && *width > UINT64_MAX / *height) fail(name, "WIDTH x HEIGHT overflows");
    points = *width * *height;
  }
  if (width && height && *height != 0 && *width <= UINT64_MAX / *height && *width * *height != *points) {
    fail(name, "POINTS " + std::to_string(*points) + " differs from WIDTH x HEIGHT = " + std::to_string(*width * *height));
  }
  const cloud_io::CloudAssembler assembler(fields, name);
  const std::string_view body = data.substr(cur.offset());
  check_point_limit(*points, max_points, name);
  if (data_kind == "binary") {
    const size_t record = assembler.record_size();
    if (*points > body.size() / record) {
      fail(name, "POINTS " + std::to_string(*points) + " of " + std::to_string(record) + " bytes need more than the " +
                     std::to_string(body.size()) + " bytes that follow the header");
    }
    assembler.begin(cloud, *points, *points);
    const auto* p = reinterpret_cast<const uint8_t*>(body.data());
    for (uint64_t i = 0; i < *points; ++i, p += record) assembler.add_binary(cloud, p, false);  // PCL writes host = little-endian
    return cloud;
  }
  assembler.begin(cloud, *points, body.size() / 2 + 1);
  cloud_io::TextCursor text(body, cur.line_number());
  std::vector<double> values(assembler.value_count());
  std::vector<uint64_t> bits(assembler.value_count());
  for (uint64_t i = 0; i < *points; ++i) {
    size_t k = 0;
    for (const auto& f : fields) {
      for (size_t c = 0; c < f.count; ++c, ++k) {
        const size_t line = text.line_number();
        const auto tok = text.token();
        if (tok.empty()) fail(name, "data ends at point " + std::to_string(i) + " of " + std::to_string(*points) + ", field '" + f.name + "'");
        if (!cloud_io::parse_scalar(tok, f.type, values[k], bits[k])) {
          // PCL writes packed rgb as the float with those bits, or as an integer.
          if (cloud_io::slot_for_name(f.name) == cloud_io::Slot::kPackedRgb &&
              cloud_io::parse_scalar(tok, Scalar::kU32, values[k], bits[k])) {
            continue;
          }
          fail(name, "line " + std::to_string(line) + ": point " + std::to_string(i) + ", field '" + f.name + "': '" +
                         std::string(tok) + "' is not a valid value");
        }
      }
    }
    assembler.add_values(cloud, values.data(), bits.data());
  }
  return cloud;
}

std::string format_pcd(const PointCloud& cloud, CloudEncoding encoding) {
  cloud.check("format_pcd");
  std::string fields = "x y z", sizes = "4 4 4", types = "F F F";
  auto add = [&](const char* n, const char* s, const char* t) {
    fields += std::string(" ") + n;
    sizes += std::string(" ") + s;
    types += std::string(" ") + t;
  };
  if (!cloud.rgb.empty()) add("rgb", "4", "U");  // packed 0x00RRGGBB
  if (!cloud.intensity.empty()) add("intensity", "4", "F");
  if (!cloud.time.empty()) add("time", "4", "F");
  if (!cloud.ring.empty()) add("ring", "2", "U");
  if (!cloud.flags.empty()) add("flags", "1", "U");
  if (!cloud.camera.empty()) add("camera", "1", "U");
  const size_t n_fields = cloud.field_names().size() - (cloud.rgb.empty() ? 0 : 2);
  std::string counts = "1";
  for (size_t i = 1; i < n_fields; ++i) counts += " 1";
  std::string out = "# .PCD v0.7 - Point Cloud Data file format (written by omniview)\n";
  if (!cloud.frame.empty() && cloud.frame.find_first_of(" \t\r\n") == std::string::npos) {
    out += "# omniview frame " + cloud.frame + "\n";
  }
  out += "# omniview stamp_ns " + cloud_io::stamp_to_string(cloud.stamp) + "\n";
  out += "VERSION 0.7\nFIELDS " + fields + "\nSIZE " + sizes + "\nTYPE " + types + "\nCOUNT " + counts + "\n";
  out += "WIDTH " + std::to_string(cloud.size()) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\n";
  out += "POINTS " + std::to_string(cloud.size()) + "\nDATA " + (encoding == CloudEncoding::kAscii ? "ascii" : "binary") + "\n";
  auto packed = [&](size_t i) {
    return (uint32_t{cloud.rgb[i][0]} << 16) | (uint32_t{cloud.rgb[i][1]} << 8) | uint32_t{cloud.rgb[i][2]};
  };
  if (encoding == CloudEncoding::kAscii) {
    char buf[64];
    for (size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.points[i];
      std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", p.x(), p.y(), p.z());
      out += buf;
      if (!cloud.rgb.empty()) cloud_io::append_word(out, packed(i));
      if (!cloud.intensity.empty()) { std::snprintf(buf, sizeof buf, " %.9g", cloud.intensity[i]); out += buf; }
      if (!cloud.time.empty()) { std::snprintf(buf, sizeof buf, " %.9g", cloud.time[i]); out += buf; }
      if (!cloud.ring.empty()) cloud_io::append_word(out, cloud.ring[i]);
      if (!cloud.flags.empty()) cloud_io::append_word(out, cloud.flags[i]);
      if (!cloud.camera.empty()) cloud_io::append_word(out, cloud.camera[i]);
      out += "\n";
    }
    return out;
  }
  for (size_t i = 0; i < cloud.size(); ++i) {
    const auto& p = cloud.points[i];
    cloud_io::put_le(out, p.x());
    cloud_io::put_le(out, p.y());
    cloud_io::put_le(out, p.z());
    if (!cloud.rgb.empty()) cloud_io::put_le(out, packed(i));
    if (!cloud.intensity.empty()) cloud_io::put_le(out, cloud.intensity[i]);
    if (!cloud.time.empty()) cloud_io::put_le(out, cloud.time[i]);
    if (!cloud.ring.empty()) cloud_io::put_le(out, cloud.ring[i]);
    if (!cloud.flags.empty()) cloud_io::put_le(out, cloud.flags[i]);
    if (!cloud.camera.empty()) cloud_io::put_le(out, cloud.camera[i]);
  }
  return out;
}

}  // namespace omniview
