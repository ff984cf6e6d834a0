// PLY (Greg Turk's polygon file format): header of `element` / `property` lines, then the
// elements in header order, as ASCII lines or packed binary records.
#include <algorithm>
#include <cmath>
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

struct PlyProperty {
  std::string name;
  Scalar type = Scalar::kF32;
  bool is_list = false;
  Scalar count_type = Scalar::kU8;  // lists: the type of the length prefix
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

std::optional<Scalar> ply_type(std::string_view t) {
  if (t == "char" || t == "int8") return Scalar::kI8;
  if (t == "uchar" || t == "uint8") return Scalar::kU8;
  if (t == "short" || t == "int16") return Scalar::kI16;
  if (t == "ushort" || t == "uint16") return Scalar::kU16;
  if (t == "int" || t == "int32") return Scalar::kI32;
  if (t == "uint" || t == "uint32") return Scalar::kU32;
  if (t == "float" || t == "float32") return Scalar::kF32;
  if (t == "double" || t == "float64") return Scalar::kF64;
  return std::nullopt;
}

enum class PlyFormat { kAscii, kLittle, kBig };

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::string frame;
  std::optional<std::chrono::system_clock::time_point> stamp;
  size_t body_offset = 0;
  size_t body_line = 1;
};

PlyHeader parse_header(std::string_view data, const std::string& name) {
  cloud_io::TextCursor cur(data);
  PlyHeader h;
  if (cur.line() != "ply") fail(name, "not a PLY file (the first line must be 'ply')");
  bool have_format = false;
  while (true) {
    if (cur.at_end()) fail(name, "header has no 'end_header' line");
    const size_t line_no = cur.line_number();
    const std::string_view line = cur.line();
    std::vector<std::string_view> w;
    cloud_io::for_each_word(line, [&](std::string_view word) { w.push_back(word); });
    const std::string where = "header line " + std::to_string(line_no);
    if (w.empty()) continue;
    if (w[0] == "end_header") break;
    if (w[0] == "comment" || w[0] == "obj_info") {
      if (w.size() >= 4 && w[0] == "comment" && w[1] == "omniview") {
        if (w[2] == "frame") h.frame = std::string(w[3]);
        std::chrono::system_clock::time_point t;
        if (w[2] == "stamp_ns" && cloud_io::stamp_from_string(w[3], t)) h.stamp = t;
      }
      continue;
    }
    if (w[0] == "format") {
      if (w.size() != 3) fail(name, where + ": 'format' needs a format and a version");
      if (w[1] == "ascii") h.format = PlyFormat::kAscii;
      else if (w[1] == "binary_little_endian") h.format = PlyFormat::kLittle;
      else if (w[1] == "binary_big_endian") h.format = PlyFormat::kBig;
      else fail(name, where + ": unknown format '" + std::string(w[1]) + "'");
      if (w[2] != "1.0") fail(name, where + ": unsupported PLY version '" + std::string(w[2]) + "'");
      have_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail(name, where + ": 'element' needs a name and a count");
      PlyElement e;
      e.name = std::string(w[1]);
      double value = 0;
      uint64_t bits = 0;
      if (!cloud_io::parse_scalar(w[2], Scalar::kU64, value, bits)) {
        fail(name, where + ": element '" + e.name + "' has a bad count '" + std::string(w[2]) + "'");
      }
      e.count = bits;
      h.elements.push_back(e);
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail(name, where + ": 'property' before any 'element'");
      PlyElement& e = h.elements.back();
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        const auto ct = ply_type(w[2]);
        const auto it = ply_type(w[3]);
        if (!ct || !it) fail(name, where + ": unknown type in list property '" + std::string(w[4]) + "'");
        if (cloud_io::scalar_is_float(*ct)) fail(name, where + ": list length type of '" + std::string(w[4]) + "' must be an integer");
        p = {std::string(w[4]), *it, true, *ct};
      } else if (w.size() == 3) {
        const auto t = ply_type(w[1]);
        if (!t) fail(name, where + ": property '" + std::string(w[2]) + "' has unknown type '" + std::string(w[1]) + "'");
        p = {std::string(w[2]), *t, false, Scalar::kU8};
      } else {
        fail(name, where + ": malformed property line");
      }
      for (const auto& q : e.properties) {
        if (q.name == p.name) fail(name, where + ": element '" + e.name + "' repeats property '" + p.name + "'");
      }
      e.properties.push_back(p);
    } else {
      fail(name, where + ": unknown keyword '" + std::string(w[0]) + "'");
    }
  }
  if (!have_format) fail(name, "header has no 'format' line");
  h.body_offset = cur.offset();
  h.body_line = cur.line_number();
  return h;
}

}  // namespace

PointCloud parse_ply(std::string_view data, const std::string& name, size_t max_points) {
  const PlyHeader h = parse_header(data, name);
  const auto vertex = std::find_if(h.elements.begin(), h.elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == h.elements.end()) fail(name, "no 'vertex' element");
  check_point_limit(vertex->count, max_points, name);
  std::vector<Field> fields;
  for (const auto& p : vertex->properties) {
    if (p.is_list) {
      if (cloud_io::slot_for_name(p.name) != cloud_io::Slot::kIgnored) fail(name, "vertex property '" + p.name + "' is a list");
      continue;
    }
    fields.push_back({p.name, p.type, 1, cloud_io::Slot::kIgnored});
  }
  const cloud_io::CloudAssembler assembler(fields, name + ": element 'vertex'");
  PointCloud cloud;
  cloud.frame = h.frame;
  if (h.stamp) cloud.stamp = *h.stamp;
  const std::string_view body = data.substr(h.body_offset);

  if (h.format == PlyFormat::kAscii) {
    cloud_io::TextCursor cur(body, h.body_line);
    // An ASCII record takes at least two bytes per value: bound what the count may reserve.
    assembler.begin(cloud, vertex->count, body.size() / 2 + 1);
    std::vector<double> values;
    std::vector<uint64_t> bits;
    for (const auto& e : h.elements) {
      const bool is_vertex = &e == &*vertex;
      if (e.properties.empty()) continue;  // records of nothing
      for (uint64_t i = 0; i < e.count; ++i) {
        values.clear();
        bits.clear();
        for (const auto& p : e.properties) {
          uint64_t n = 1;
          double v = 0;
          uint64_t b = 0;
          if (p.is_list) {
            const size_t line = cur.line_number();
            const auto tok = cur.token();
            if (!cloud_io::parse_scalar(tok, p.count_type, v, b)) {
              fail(name, "line " + std::to_string(line) + ": element '" + e.name + "' " + std::to_string(i) + ", list '" +
                             p.name + "': bad length '" + std::string(tok) + "'");
            }
            n = b;
          }
          for (uint64_t k = 0; k < n; ++k) {
            const size_t line = cur.line_number();
            const auto tok = cur.token();
            if (tok.empty()) {
              fail(name, "data ends in element '" + e.name + "' " + std::to_string(i) + " of " + std::to_string(e.count) +
                             ", property '" + p.name + "'");
            }
            if (!cloud_io::parse_scalar(tok, p.type, v, b)) {
              fail(name, "line " + std::to_string(line) + ": element '" + e.name + "' " + std::to_string(i) +
                             ", property '" + p.name + "': '" + std::string(tok) + "' is not a valid value");
            }
            if (is_vertex && !p.is_list) {
              values.push_back(v);
              bits.push_back(b);
            }
          }
        }
        if (is_vertex) assembler.add_values(cloud, values.data(), bits.data());
      }
    }
    return cloud;
  }

  const bool big = h.format == PlyFormat::kBig;
  const auto* p = reinterpret_cast<const uint8_t*>(body.data());
  const uint8_t* end = p + body.size();
  for (const auto& e : h.elements) {
    const bool is_vertex = &e == &*vertex;
    const bool fixed = std::none_of(e.properties.begin(), e.properties.end(), [](const PlyProperty& q) { return q.is_list; });
    size_t record = 0;
    for (const auto& q : e.properties) record += q.is_list ? 0 : cloud_io::scalar_size(q.type);
    if (fixed) {
      const size_t left = static_cast<size_t>(end - p);
      if (record > 0 && e.count > left / record) {
        fail(name, "element '" + e.name + "' declares " + std::to_string(e.count) + " records of " + std::to_string(record) +
                       " bytes, but only " + std::to_string(left) + " bytes follow");
      }
      if (is_vertex) {
        assembler.begin(cloud, e.count, e.count);
        for (uint64_t i = 0; i < e.count; ++i, p += record) assembler.add_binary(cloud, p, big);
      } else {
        p += record * e.count;
      }
      continue;
    }
    // Records with lists (a mesh's faces): walk them one by one. The vertex element with
    // a list property keeps its scalar properties only.
    if (is_vertex) assembler.begin(cloud, e.count, static_cast<size_t>(end - p));
    std::vector<uint8_t> packed;
    for (uint64_t i = 0; i < e.count; ++i) {
      packed.clear();
      for (const auto& q : e.properties) {
        const size_t lead = cloud_io::scalar_size(q.is_list ? q.count_type : q.type);
        if (static_cast<size_t>(end - p) < lead) {
          fail(name, "data ends in element '" + e.name + "' " + std::to_string(i) + " of " + std::to_string(e.count) +
                         ", property '" + q.name + "'");
        }
        if (!q.is_list) {
          packed.insert(packed.end(), p, p + lead);
          p += lead;
          continue;
        }
        uint64_t n = 0;
        cloud_io::read_scalar(p, q.count_type, big, &n);
        p += lead;
        const size_t item = cloud_io::scalar_size(q.type);
        if (n > static_cast<size_t>(end - p) / item) {
          fail(name, "element '" + e.name + "' " + std::to_string(i) + ", list '" + q.name + "' of " + std::to_string(n) +
                         " items runs past the end of the data");
        }
        p += n * item;
      }
      if (is_vertex) assembler.add_binary(cloud, packed.data(), big);
    }
  }
  return cloud;
}

std::string format_ply(const PointCloud& cloud, CloudEncoding encoding) {
  cloud.check("format_ply");
  std::string out = "ply\nformat ";
  out += encoding == CloudEncoding::kAscii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  out += "comment written by omniview\n";
  if (!cloud.frame.empty() && cloud.frame.find_first_of(" \t\r\n") == std::string::npos) {
    out += "comment omniview frame " + cloud.frame + "\n";
  }
  out += "comment omniview stamp_ns " + cloud_io::stamp_to_string(cloud.stamp) + "\n";
  out += "element vertex " + std::to_string(cloud.size()) + "\n";
  out += "property float x\nproperty float y\nproperty float z\n";
  if (!cloud.rgb.empty()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (!cloud.intensity.empty()) out += "property float intensity\n";
  if (!cloud.time.empty()) out += "property float time\n";
  if (!cloud.ring.empty()) out += "property ushort ring\n";
  if (!cloud.flags.empty()) out += "property uchar flags\n";
  if (!cloud.camera.empty()) out += "property uchar camera\n";
  out += "end_header\n";
  if (encoding == CloudEncoding::kAscii) {
    char buf[64];
    for (size_t i = 0; i < cloud.size(); ++i) {
      const auto& p = cloud.points[i];
      // %.9g round-trips a float exactly.
      std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g", p.x(), p.y(), p.z());
      out += buf;
      if (!cloud.rgb.empty()) { cloud_io::append_word(out, cloud.rgb[i][0]); cloud_io::append_word(out, cloud.rgb[i][1]); cloud_io::append_word(out, cloud.rgb[i][2]); }
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
    if (!cloud.rgb.empty()) out.append(reinterpret_cast<const char*>(cloud.rgb[i].data()), 3);
    if (!cloud.intensity.empty()) cloud_io::put_le(out, cloud.intensity[i]);
    if (!cloud.time.empty()) cloud_io::put_le(out, cloud.time[i]);
    if (!cloud.ring.empty()) cloud_io::put_le(out, cloud.ring[i]);
    if (!cloud.flags.empty()) cloud_io::put_le(out, cloud.flags[i]);
    if (!cloud.camera.empty()) cloud_io::put_le(out, cloud.camera[i]);
  }
  return out;
}

}  // namespace omniview
