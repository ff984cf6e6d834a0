#include "server/api/request_bounds.h"

#include <cmath>
#include <sstream>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include "core/io/quote.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

grpc::Status refuse(const std::string& field, const std::string& why) {
  return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, field + ": " + why);
}

grpc::Status check_text(const std::string& field, const std::string& value) {
  if (value.size() > kMaxRequestText) {
    return refuse(field, "is " + std::to_string(value.size()) + " characters long; at most " +
                             std::to_string(kMaxRequestText) + " are accepted (got " + quote_prefix(value) + ")");
  }
  for (const char c : value) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) return refuse(field, "must not hold control characters (got " + quote_prefix(value) + ")");
  }
  return grpc::Status::OK;
}

grpc::Status check_number(const std::string& field, double value) {
  if (std::isfinite(value)) return grpc::Status::OK;
  std::ostringstream text;
  text << value;
  return refuse(field, "must be a finite number, got " + text.str());
}

grpc::Status check_message(const Message& m, const std::string& prefix);

// A map entry is named by its key ("positions[elbow]"), a list entry by its index.
std::string entry_name(const std::string& field, const Message& entry, int index) {
  const auto* key = entry.GetDescriptor()->map_key();
  if (key && key->type() == FieldDescriptor::TYPE_STRING) {
    const std::string k = entry.GetReflection()->GetString(entry, key);
    if (k.size() <= 40) return field + "[" + k + "]";
  }
  return field + "[" + std::to_string(index) + "]";
}

grpc::Status check_field(const Message& m, const FieldDescriptor* f, const std::string& name) {
  const auto* r = m.GetReflection();
  // Maps are checked through their generated API (check_request_bounds): reflection over a
  // map rebuilds a repeated view of it, which crashed under ThreadSanitizer.
  if (f->is_map()) return grpc::Status::OK;
  if (f->is_repeated()) {
    const int n = r->FieldSize(m, f);
    if (n > kMaxRequestListEntries) {
      return refuse(name, "has " + std::to_string(n) + " entries; at most " + std::to_string(kMaxRequestListEntries) +
                              " are accepted");
    }
    for (int i = 0; i < n; ++i) {
      grpc::Status s;
      switch (f->cpp_type()) {
        case FieldDescriptor::CPPTYPE_STRING:
          s = check_text(name + "[" + std::to_string(i) + "]", r->GetRepeatedString(m, f, i));
          break;
        case FieldDescriptor::CPPTYPE_DOUBLE:
          s = check_number(name + "[" + std::to_string(i) + "]", r->GetRepeatedDouble(m, f, i));
          break;
        case FieldDescriptor::CPPTYPE_FLOAT:
          s = check_number(name + "[" + std::to_string(i) + "]", r->GetRepeatedFloat(m, f, i));
          break;
        case FieldDescriptor::CPPTYPE_MESSAGE: {
          const Message& entry = r->GetRepeatedMessage(m, f, i);
          s = check_message(entry, entry_name(name, entry, i));
          break;
        }
        default:
          break;
      }
      if (!s.ok()) return s;
    }
    return grpc::Status::OK;
  }
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_STRING:
      // bytes fields carry data, not names; no request has one today.
      return f->type() == FieldDescriptor::TYPE_BYTES ? grpc::Status::OK : check_text(name, r->GetString(m, f));
    case FieldDescriptor::CPPTYPE_DOUBLE:
      return check_number(name, r->GetDouble(m, f));
    case FieldDescriptor::CPPTYPE_FLOAT:
      return check_number(name, r->GetFloat(m, f));
    case FieldDescriptor::CPPTYPE_MESSAGE:
      return r->HasField(m, f) ? check_message(r->GetMessage(m, f), name) : grpc::Status::OK;
    default:
      return grpc::Status::OK;
  }
}

grpc::Status check_message(const Message& m, const std::string& prefix) {
  const auto* d = m.GetDescriptor();
  const bool map_entry = d->options().map_entry();
  for (int i = 0; i < d->field_count(); ++i) {
    const FieldDescriptor* f = d->field(i);
    // A map entry's fields are the entry itself ("positions[elbow]"), not ".key"/".value".
    const std::string name = map_entry ? prefix + (f->name() == "key" ? " (the key)" : "")
                                       : (prefix.empty() ? f->name() : prefix + "." + f->name());
    if (const grpc::Status s = check_field(m, f, name); !s.ok()) return s;
  }
  return grpc::Status::OK;
}

std::string number(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

// What a cloud request's options mean, beyond finite numbers and short names.
grpc::Status check_cloud_options(const v1::CloudOptions& o) {
  const double voxel = o.voxel_size_m();
  if (voxel != 0 && !(voxel >= kMinCloudVoxelM && voxel <= kMaxCloudVoxelM)) {
    return refuse("options.voxel_size_m", "must be 0 (every point) or " + number(kMinCloudVoxelM) + ".." +
                                             number(kMaxCloudVoxelM) + " m, got " + number(voxel));
  }
  if (o.has_crop()) {
    const auto& c = o.crop();
    if (!c.has_min() || !c.has_max()) return refuse("options.crop", "needs both min and max");
    const double lo[3] = {c.min().x(), c.min().y(), c.min().z()};
    const double hi[3] = {c.max().x(), c.max().y(), c.max().z()};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      if (std::abs(lo[i]) > kMaxCloudCropM || std::abs(hi[i]) > kMaxCloudCropM) {
        return refuse(std::string("options.crop.") + axis[i], "must lie within +-" + number(kMaxCloudCropM) +
                                                                  " m, got " + number(lo[i]) + ".." + number(hi[i]));
      }
      if (!(lo[i] < hi[i])) {
        return refuse(std::string("options.crop.min.") + axis[i],
                      "must be less than options.crop.max." + std::string(axis[i]) + " (got min " + number(lo[i]) +
                          ", max " + number(hi[i]) + ")");
      }
    }
  }
  if (!v1::Fusion_IsValid(o.fusion())) {
    return refuse("options.fusion", "unknown value " + std::to_string(o.fusion()) + " (NEAREST_CENTRE or BLEND)");
  }
  return grpc::Status::OK;
}

}  // namespace

grpc::Status check_cloud_request(const Message& request) {
  if (const auto* stream = dynamic_cast<const v1::StreamCloudsRequest*>(&request)) {
    if (!(stream->max_rate_hz() >= 0)) {
      return refuse("max_rate_hz", "must be >= 0 (0: as fast as clouds come), got " + number(stream->max_rate_hz()));
    }
    return check_cloud_options(stream->options());
  }
  if (const auto* get = dynamic_cast<const v1::GetCloudRequest*>(&request)) {
    if (get->timeout_ms() < 0 || get->timeout_ms() > kMaxCloudWaitMs) {
      return refuse("timeout_ms", "must be 0.." + std::to_string(kMaxCloudWaitMs) + " (0: 5000), got " +
                                      std::to_string(get->timeout_ms()));
    }
    return check_cloud_options(get->options());
  }
  return grpc::Status::OK;
}

grpc::Status check_request_bounds(const Message& request) {
  if (const auto* joints = dynamic_cast<const v1::SetJointPositionsRequest*>(&request)) {
    const auto& positions = joints->positions();
    if (positions.size() > static_cast<size_t>(kMaxRequestListEntries)) {
      return refuse("positions", "has " + std::to_string(positions.size()) + " entries; at most " +
                                     std::to_string(kMaxRequestListEntries) + " are accepted");
    }
    for (const auto& [joint, value] : positions) {
      if (grpc::Status s = check_text("positions (the key)", joint); !s.ok()) return s;
      const std::string entry = joint.size() <= 40 ? "positions[" + joint + "]" : "positions[...]";
      if (grpc::Status s = check_number(entry, value); !s.ok()) return s;
    }
  }
  if (grpc::Status s = check_message(request, ""); !s.ok()) return s;
  return check_cloud_request(request);
}

}  // namespace omniview
