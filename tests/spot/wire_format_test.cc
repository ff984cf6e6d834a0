// Pins our bosdyn.api subset (spot_adapter/proto) to the public Spot API's wire format:
// every field number and type, every enum value, every service method name, the raw bytes of
// the numbers that are easy to get wrong, and the method paths the generated gRPC servers
// answer on. The expected numbers below were checked against Boston Dynamics' public
// spot-sdk protos (protos/bosdyn/api/*.proto, v5.1.4). Adding a field to a .proto without
// adding it here fails CompletenessTest: check the new number upstream first.

#include <chrono>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/unknown_field_set.h>
#include <google/protobuf/util/message_differencer.h>
#include <google/protobuf/wrappers.pb.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "bosdyn/api/auth_service.grpc.pb.h"
#include "bosdyn/api/directory_service.grpc.pb.h"
#include "bosdyn/api/image_service.grpc.pb.h"
#include "bosdyn/api/point_cloud_service.grpc.pb.h"
#include "bosdyn/api/robot_id_service.grpc.pb.h"
#include "bosdyn/api/robot_state_service.grpc.pb.h"
#include "bosdyn/api/time_sync_service.grpc.pb.h"

namespace {

namespace api = bosdyn::api;
using google::protobuf::Descriptor;
using google::protobuf::DoubleValue;
using google::protobuf::DescriptorPool;
using google::protobuf::EnumDescriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::FileDescriptor;

const std::vector<std::string> kFiles = {
    "bosdyn/api/header.proto",       "bosdyn/api/geometry.proto",
    "bosdyn/api/auth.proto",         "bosdyn/api/auth_service.proto",
    "bosdyn/api/directory.proto",    "bosdyn/api/directory_service.proto",
    "bosdyn/api/robot_id.proto",     "bosdyn/api/robot_id_service.proto",
    "bosdyn/api/image.proto",        "bosdyn/api/image_service.proto",
    "bosdyn/api/point_cloud.proto",  "bosdyn/api/point_cloud_service.proto",
    "bosdyn/api/robot_state.proto",  "bosdyn/api/robot_state_service.proto",
    "bosdyn/api/time_sync.proto",    "bosdyn/api/time_sync_service.proto",
};

std::string Hex(const std::string& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (unsigned char c : bytes) {
    if (!out.empty()) out += ' ';
    out += digits[c >> 4];
    out += digits[c & 15];
  }
  return out;
}

// ---------------------------------------------------------------------------------------
// Every field: message, field, number, type (scalar name, or the full name of the message or
// enum, or "map<K,V>"), repeated, oneof.

struct FieldSpec {
  const char* message;
  const char* field;
  int number;
  const char* type;
  bool repeated = false;
  const char* oneof = "";
};

constexpr bool R = true;  // repeated

const std::vector<FieldSpec> kFields = {
    // header.proto
    {"RequestHeader", "request_timestamp", 1, "google.protobuf.Timestamp"},
    {"RequestHeader", "client_name", 2, "string"},
    {"RequestHeader", "disable_rpc_logging", 3, "bool"},
    {"CommonError", "code", 1, "bosdyn.api.CommonError.Code"},
    {"CommonError", "message", 2, "string"},
    {"ResponseHeader", "request_header", 1, "bosdyn.api.RequestHeader"},
    {"ResponseHeader", "request_received_timestamp", 2, "google.protobuf.Timestamp"},
    {"ResponseHeader", "response_timestamp", 3, "google.protobuf.Timestamp"},
    {"ResponseHeader", "error", 4, "bosdyn.api.CommonError"},
    // geometry.proto
    {"Vec2", "x", 1, "double"},
    {"Vec2", "y", 2, "double"},
    {"Vec3", "x", 1, "double"},
    {"Vec3", "y", 2, "double"},
    {"Vec3", "z", 3, "double"},
    {"Quaternion", "x", 1, "double"},
    {"Quaternion", "y", 2, "double"},
    {"Quaternion", "z", 3, "double"},
    {"Quaternion", "w", 4, "double"},
    {"SE3Pose", "position", 1, "bosdyn.api.Vec3"},
    {"SE3Pose", "rotation", 2, "bosdyn.api.Quaternion"},
    {"FrameTreeSnapshot.ParentEdge", "parent_frame_name", 1, "string"},
    {"FrameTreeSnapshot.ParentEdge", "parent_tform_child", 2, "bosdyn.api.SE3Pose"},
    {"FrameTreeSnapshot", "child_to_parent_edge_map", 1,
     "map<string,bosdyn.api.FrameTreeSnapshot.ParentEdge>", R},
    // auth.proto
    {"GetAuthTokenRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"GetAuthTokenRequest", "username", 2, "string"},
    {"GetAuthTokenRequest", "password", 3, "string"},
    {"GetAuthTokenRequest", "token", 4, "string"},
    {"GetAuthTokenResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"GetAuthTokenResponse", "status", 2, "bosdyn.api.GetAuthTokenResponse.Status"},
    {"GetAuthTokenResponse", "token", 3, "string"},
    // directory.proto
    {"ServiceEntry", "name", 1, "string"},
    {"ServiceEntry", "type", 2, "string", false, "service_type"},
    {"ServiceEntry", "authority", 3, "string"},
    {"ServiceEntry", "last_update", 4, "google.protobuf.Timestamp"},
    {"ServiceEntry", "user_token_required", 5, "bool"},
    {"ServiceEntry", "permission_required", 7, "string"},
    {"ServiceEntry", "liveness_timeout_secs", 8, "double"},
    {"GetServiceEntryRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"GetServiceEntryRequest", "service_name", 2, "string"},
    {"GetServiceEntryResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"GetServiceEntryResponse", "status", 2, "bosdyn.api.GetServiceEntryResponse.Status"},
    {"GetServiceEntryResponse", "service_entry", 3, "bosdyn.api.ServiceEntry"},
    {"ListServiceEntriesRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"ListServiceEntriesResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"ListServiceEntriesResponse", "service_entries", 2, "bosdyn.api.ServiceEntry", R},
    // robot_id.proto
    {"RobotId", "serial_number", 1, "string"},
    {"RobotId", "species", 2, "string"},
    {"RobotId", "version", 3, "string"},
    {"RobotId", "nickname", 5, "string"},
    {"RobotId", "computer_serial_number", 6, "string"},
    {"RobotIdRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"RobotIdResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"RobotIdResponse", "robot_id", 2, "bosdyn.api.RobotId"},
    // image.proto
    {"Image", "cols", 2, "int32"},
    {"Image", "rows", 3, "int32"},
    {"Image", "data", 4, "bytes"},
    {"Image", "format", 5, "bosdyn.api.Image.Format"},
    {"Image", "pixel_format", 6, "bosdyn.api.Image.PixelFormat"},
    {"CaptureParameters", "exposure_duration", 1, "google.protobuf.Duration"},
    {"CaptureParameters", "gain", 2, "double"},
    {"ImageCapture", "image", 3, "bosdyn.api.Image"},
    {"ImageCapture", "capture_params", 4, "bosdyn.api.CaptureParameters"},
    {"ImageCapture", "frame_name_image_sensor", 5, "string"},
    {"ImageCapture", "acquisition_time", 30, "google.protobuf.Timestamp"},
    {"ImageCapture", "transforms_snapshot", 31, "bosdyn.api.FrameTreeSnapshot"},
    {"ImageSource.PinholeModel.CameraIntrinsics", "focal_length", 1, "bosdyn.api.Vec2"},
    {"ImageSource.PinholeModel.CameraIntrinsics", "principal_point", 2, "bosdyn.api.Vec2"},
    {"ImageSource.PinholeModel.CameraIntrinsics", "skew", 3, "bosdyn.api.Vec2"},
    {"ImageSource.PinholeModel", "intrinsics", 1,
     "bosdyn.api.ImageSource.PinholeModel.CameraIntrinsics"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "pinhole_intrinsics", 1,
     "bosdyn.api.ImageSource.PinholeModel.CameraIntrinsics"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "k1", 2, "float"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "k2", 3, "float"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "p1", 4, "float"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "p2", 5, "float"},
    {"ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics", "k3", 6, "float"},
    {"ImageSource.PinholeBrownConrady", "intrinsics", 1,
     "bosdyn.api.ImageSource.PinholeBrownConrady.PinholeBrownConradyIntrinsics"},
    {"ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics", "pinhole_intrinsics", 1,
     "bosdyn.api.ImageSource.PinholeModel.CameraIntrinsics"},
    {"ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics", "k1", 2, "float"},
    {"ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics", "k2", 3, "float"},
    {"ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics", "k3", 4, "float"},
    {"ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics", "k4", 5, "float"},
    {"ImageSource.KannalaBrandtModel", "intrinsics", 1,
     "bosdyn.api.ImageSource.KannalaBrandtModel.KannalaBrandtIntrinsics"},
    {"ImageSource", "name", 2, "string"},
    {"ImageSource", "cols", 4, "int32"},
    {"ImageSource", "rows", 5, "int32"},
    {"ImageSource", "depth_scale", 6, "double"},
    {"ImageSource", "pinhole", 8, "bosdyn.api.ImageSource.PinholeModel", false, "camera_models"},
    {"ImageSource", "image_type", 9, "bosdyn.api.ImageSource.ImageType"},
    {"ImageSource", "pixel_formats", 10, "bosdyn.api.Image.PixelFormat", R},
    {"ImageSource", "image_formats", 11, "bosdyn.api.Image.Format", R},
    {"ImageSource", "pinhole_brown_conrady", 13, "bosdyn.api.ImageSource.PinholeBrownConrady",
     false, "camera_models"},
    {"ImageSource", "kannala_brandt", 14, "bosdyn.api.ImageSource.KannalaBrandtModel", false,
     "camera_models"},
    {"ListImageSourcesRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"ListImageSourcesResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"ListImageSourcesResponse", "image_sources", 2, "bosdyn.api.ImageSource", R},
    {"ListImageSourcesResponse", "transforms_snapshot", 3, "bosdyn.api.FrameTreeSnapshot"},
    {"ImageRequest", "image_source_name", 1, "string"},
    {"ImageRequest", "quality_percent", 2, "double"},
    {"ImageRequest", "image_format", 3, "bosdyn.api.Image.Format"},
    {"ImageRequest", "resize_ratio", 4, "double"},
    {"ImageRequest", "pixel_format", 5, "bosdyn.api.Image.PixelFormat"},
    {"ImageRequest", "fallback_formats", 7, "bosdyn.api.Image.PixelFormat", R},
    {"GetImageRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"GetImageRequest", "image_requests", 2, "bosdyn.api.ImageRequest", R},
    {"ImageResponse", "shot", 1, "bosdyn.api.ImageCapture"},
    {"ImageResponse", "source", 2, "bosdyn.api.ImageSource"},
    {"ImageResponse", "status", 4, "bosdyn.api.ImageResponse.Status"},
    {"GetImageResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"GetImageResponse", "image_responses", 2, "bosdyn.api.ImageResponse", R},
    // point_cloud.proto
    {"PointCloudSource", "name", 1, "string"},
    {"PointCloudSource", "frame_name_sensor", 3, "string"},
    {"PointCloudSource", "supported_cloud_types", 4,
     "bosdyn.api.PointCloudRequest.PointCloudType", R},
    {"PointCloudSource", "acquisition_time", 30, "google.protobuf.Timestamp"},
    {"PointCloudSource", "transforms_snapshot", 31, "bosdyn.api.FrameTreeSnapshot"},
    {"PointCloud.EncodingParameters", "scale_factor", 1, "int32"},
    {"PointCloud.EncodingParameters", "max_x", 2, "double"},
    {"PointCloud.EncodingParameters", "max_y", 3, "double"},
    {"PointCloud.EncodingParameters", "max_z", 4, "double"},
    {"PointCloud.EncodingParameters", "remapping_constant", 5, "double"},
    {"PointCloud.EncodingParameters", "bytes_per_point", 6, "int32"},
    {"PointCloud", "source", 1, "bosdyn.api.PointCloudSource"},
    {"PointCloud", "num_points", 2, "int32"},
    {"PointCloud", "encoding", 3, "bosdyn.api.PointCloud.Encoding"},
    {"PointCloud", "encoding_parameters", 4, "bosdyn.api.PointCloud.EncodingParameters"},
    {"PointCloud", "data", 5, "bytes"},
    {"LidarPointCloud", "point_cloud", 1, "bosdyn.api.PointCloud"},
    {"LidarPointCloud", "num_beams", 2, "int32"},
    {"LidarPointCloud", "num_scans", 3, "int32"},
    {"ListPointCloudSourcesRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"ListPointCloudSourcesResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"ListPointCloudSourcesResponse", "point_cloud_sources", 2, "bosdyn.api.PointCloudSource",
     R},
    {"PointCloudRequest", "point_cloud_source_name", 1, "string"},
    {"PointCloudRequest", "cloud_type", 2, "bosdyn.api.PointCloudRequest.PointCloudType"},
    {"PointCloudRequest", "downsample_rate", 3, "int32"},
    {"GetPointCloudRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"GetPointCloudRequest", "point_cloud_requests", 2, "bosdyn.api.PointCloudRequest", R},
    {"PointCloudResponse", "status", 1, "bosdyn.api.PointCloudResponse.Status"},
    {"PointCloudResponse", "point_cloud", 2, "bosdyn.api.PointCloud", false, "cloud_data"},
    {"PointCloudResponse", "lidar_cloud", 3, "bosdyn.api.LidarPointCloud", false, "cloud_data"},
    {"PointCloudResponse", "no_update", 4, "bool"},
    {"PointCloudResponse", "expected_time_to_next_update", 5, "int32"},
    {"GetPointCloudResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"GetPointCloudResponse", "point_cloud_responses", 4, "bosdyn.api.PointCloudResponse", R},
    // robot_state.proto
    {"JointState", "name", 1, "string"},
    {"JointState", "position", 2, "google.protobuf.DoubleValue"},
    {"KinematicState", "joint_states", 2, "bosdyn.api.JointState", R},
    {"KinematicState", "acquisition_timestamp", 30, "google.protobuf.Timestamp"},
    {"KinematicState", "transforms_snapshot", 31, "bosdyn.api.FrameTreeSnapshot"},
    {"RobotState", "kinematic_state", 6, "bosdyn.api.KinematicState"},
    {"RobotStateRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"RobotStateResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"RobotStateResponse", "robot_state", 2, "bosdyn.api.RobotState"},
    // time_sync.proto
    {"TimeSyncRoundTrip", "client_tx", 1, "google.protobuf.Timestamp"},
    {"TimeSyncRoundTrip", "server_rx", 2, "google.protobuf.Timestamp"},
    {"TimeSyncRoundTrip", "server_tx", 3, "google.protobuf.Timestamp"},
    {"TimeSyncRoundTrip", "client_rx", 4, "google.protobuf.Timestamp"},
    {"TimeSyncEstimate", "round_trip_time", 1, "google.protobuf.Duration"},
    {"TimeSyncEstimate", "clock_skew", 2, "google.protobuf.Duration"},
    {"TimeSyncState", "best_estimate", 1, "bosdyn.api.TimeSyncEstimate"},
    {"TimeSyncState", "status", 2, "bosdyn.api.TimeSyncState.Status"},
    {"TimeSyncState", "measurement_time", 3, "google.protobuf.Timestamp"},
    {"TimeSyncUpdateRequest", "header", 1, "bosdyn.api.RequestHeader"},
    {"TimeSyncUpdateRequest", "previous_round_trip", 2, "bosdyn.api.TimeSyncRoundTrip"},
    {"TimeSyncUpdateRequest", "clock_identifier", 3, "string"},
    {"TimeSyncUpdateResponse", "header", 1, "bosdyn.api.ResponseHeader"},
    {"TimeSyncUpdateResponse", "previous_estimate", 2, "bosdyn.api.TimeSyncEstimate"},
    {"TimeSyncUpdateResponse", "state", 3, "bosdyn.api.TimeSyncState"},
    {"TimeSyncUpdateResponse", "clock_identifier", 4, "string"},
};

struct EnumSpec {
  const char* enum_name;
  std::vector<std::pair<const char*, int>> values;
};

const std::vector<EnumSpec> kEnums = {
    {"CommonError.Code",
     {{"CODE_UNSPECIFIED", 0}, {"CODE_OK", 1}, {"CODE_INTERNAL_SERVER_ERROR", 2},
      {"CODE_INVALID_REQUEST", 3}}},
    {"GetAuthTokenResponse.Status",
     {{"STATUS_UNKNOWN", 0}, {"STATUS_OK", 1}, {"STATUS_INVALID_LOGIN", 2},
      {"STATUS_INVALID_TOKEN", 3}, {"STATUS_TEMPORARILY_LOCKED_OUT", 4}}},
    {"GetServiceEntryResponse.Status",
     {{"STATUS_UNKNOWN", 0}, {"STATUS_OK", 1}, {"STATUS_NONEXISTENT_SERVICE", 2}}},
    {"Image.Format",
     {{"FORMAT_UNKNOWN", 0}, {"FORMAT_JPEG", 1}, {"FORMAT_RAW", 2}, {"FORMAT_RLE", 3}}},
    {"Image.PixelFormat",
     {{"PIXEL_FORMAT_UNKNOWN", 0}, {"PIXEL_FORMAT_GREYSCALE_U8", 1}, {"PIXEL_FORMAT_RGB_U8", 3},
      {"PIXEL_FORMAT_RGBA_U8", 4}, {"PIXEL_FORMAT_DEPTH_U16", 5},
      {"PIXEL_FORMAT_GREYSCALE_U16", 6}}},
    {"ImageSource.ImageType",
     {{"IMAGE_TYPE_UNKNOWN", 0}, {"IMAGE_TYPE_VISUAL", 1}, {"IMAGE_TYPE_DEPTH", 2}}},
    {"ImageResponse.Status",
     {{"STATUS_UNKNOWN", 0}, {"STATUS_OK", 1}, {"STATUS_UNKNOWN_CAMERA", 2},
      {"STATUS_SOURCE_DATA_ERROR", 3}, {"STATUS_IMAGE_DATA_ERROR", 4},
      {"STATUS_UNSUPPORTED_IMAGE_FORMAT_REQUESTED", 5},
      {"STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED", 6},
      {"STATUS_UNSUPPORTED_RESIZE_RATIO_REQUESTED", 7}, {"STATUS_CUSTOM_PARAMS_ERROR", 8}}},
    {"PointCloud.Encoding",
     {{"ENCODING_UNKNOWN", 0}, {"ENCODING_XYZ_32F", 1}, {"ENCODING_XYZ_4SC", 2},
      {"ENCODING_XYZ_5SC", 3}}},
    {"PointCloudRequest.PointCloudType",
     {{"CLOUD_TYPE_UNKNOWN", 0}, {"CLOUD_TYPE_POINTS", 1}, {"CLOUD_TYPE_LIDAR", 2}}},
    {"PointCloudResponse.Status",
     {{"STATUS_UNKNOWN", 0}, {"STATUS_OK", 1}, {"STATUS_SOURCE_DATA_ERROR", 2},
      {"STATUS_POINT_CLOUD_DATA_ERROR", 3}, {"STATUS_UNKNOWN_SOURCE", 4},
      {"STATUS_UNSUPPORTED_CLOUD_TYPE", 5}}},
    {"TimeSyncState.Status",
     {{"STATUS_UNKNOWN", 0}, {"STATUS_OK", 1}, {"STATUS_MORE_SAMPLES_NEEDED", 2},
      {"STATUS_SERVICE_NOT_READY", 3}}},
};

struct MethodSpec {
  const char* full_name;  // bosdyn.api.<Service>.<Rpc>
  const char* input;
  const char* output;
};

const std::vector<std::pair<const char*, std::vector<MethodSpec>>> kServices = {
    {"bosdyn.api.AuthService",
     {{"bosdyn.api.AuthService.GetAuthToken", "GetAuthTokenRequest", "GetAuthTokenResponse"}}},
    {"bosdyn.api.DirectoryService",
     {{"bosdyn.api.DirectoryService.GetServiceEntry", "GetServiceEntryRequest",
       "GetServiceEntryResponse"},
      {"bosdyn.api.DirectoryService.ListServiceEntries", "ListServiceEntriesRequest",
       "ListServiceEntriesResponse"}}},
    {"bosdyn.api.RobotIdService",
     {{"bosdyn.api.RobotIdService.GetRobotId", "RobotIdRequest", "RobotIdResponse"}}},
    {"bosdyn.api.ImageService",
     {{"bosdyn.api.ImageService.ListImageSources", "ListImageSourcesRequest",
       "ListImageSourcesResponse"},
      {"bosdyn.api.ImageService.GetImage", "GetImageRequest", "GetImageResponse"}}},
    {"bosdyn.api.PointCloudService",
     {{"bosdyn.api.PointCloudService.ListPointCloudSources", "ListPointCloudSourcesRequest",
       "ListPointCloudSourcesResponse"},
      {"bosdyn.api.PointCloudService.GetPointCloud", "GetPointCloudRequest",
       "GetPointCloudResponse"}}},
    {"bosdyn.api.RobotStateService",
     {{"bosdyn.api.RobotStateService.GetRobotState", "RobotStateRequest",
       "RobotStateResponse"}}},
    {"bosdyn.api.TimeSyncService",
     {{"bosdyn.api.TimeSyncService.TimeSyncUpdate", "TimeSyncUpdateRequest",
       "TimeSyncUpdateResponse"}}},
};

const DescriptorPool* Pool() { return DescriptorPool::generated_pool(); }

std::string TypeOf(const FieldDescriptor* f) {
  if (f->is_map()) {
    return "map<" + TypeOf(f->message_type()->map_key()) + "," +
           TypeOf(f->message_type()->map_value()) + ">";
  }
  if (f->message_type() != nullptr) return f->message_type()->full_name();
  if (f->enum_type() != nullptr) return f->enum_type()->full_name();
  return FieldDescriptor::TypeName(f->type());
}

// All messages (nested ones too, map entries excepted) declared in `file`.
void CollectMessages(const Descriptor* d, std::vector<const Descriptor*>* out) {
  if (d->options().map_entry()) return;
  out->push_back(d);
  for (int i = 0; i < d->nested_type_count(); ++i) CollectMessages(d->nested_type(i), out);
}

std::vector<const Descriptor*> AllMessages() {
  std::vector<const Descriptor*> out;
  for (const auto& name : kFiles) {
    const FileDescriptor* file = Pool()->FindFileByName(name);
    if (file == nullptr) continue;
    for (int i = 0; i < file->message_type_count(); ++i) {
      CollectMessages(file->message_type(i), &out);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------

TEST(SpotProtoFiles, AllFilesArePackageBosdynApiProto3) {
  for (const auto& name : kFiles) {
    const FileDescriptor* file = Pool()->FindFileByName(name);
    ASSERT_NE(file, nullptr) << name;
    EXPECT_EQ(file->package(), "bosdyn.api") << name;
    EXPECT_EQ(file->syntax(), FileDescriptor::SYNTAX_PROTO3) << name;
    // Only well-known types and our own files may be imported.
    for (int i = 0; i < file->dependency_count(); ++i) {
      const std::string& dep = file->dependency(i)->name();
      const bool ours = dep.rfind("bosdyn/api/", 0) == 0;
      const bool wkt = dep == "google/protobuf/timestamp.proto" ||
                       dep == "google/protobuf/duration.proto" ||
                       dep == "google/protobuf/wrappers.proto" ||
                       dep == "google/protobuf/any.proto";
      EXPECT_TRUE(ours || wkt) << name << " imports " << dep;
    }
  }
}

TEST(SpotProtoFields, NumbersAndTypesMatchTheSpotApi) {
  for (const auto& spec : kFields) {
    const std::string message = std::string("bosdyn.api.") + spec.message;
    const Descriptor* d = Pool()->FindMessageTypeByName(message);
    ASSERT_NE(d, nullptr) << message;
    const FieldDescriptor* f = d->FindFieldByName(spec.field);
    ASSERT_NE(f, nullptr) << message << "." << spec.field;
    EXPECT_EQ(f->number(), spec.number) << message << "." << spec.field;
    EXPECT_EQ(TypeOf(f), spec.type) << message << "." << spec.field;
    EXPECT_EQ(f->is_repeated(), spec.repeated) << message << "." << spec.field;
    const std::string oneof =
        f->real_containing_oneof() != nullptr ? f->real_containing_oneof()->name() : "";
    EXPECT_EQ(oneof, spec.oneof) << message << "." << spec.field;
  }
}

TEST(SpotProtoFields, CompletenessEveryDeclaredFieldIsPinned) {
  std::set<std::pair<std::string, std::string>> pinned;
  for (const auto& spec : kFields) {
    pinned.emplace(std::string("bosdyn.api.") + spec.message, spec.field);
  }
  size_t declared = 0;
  for (const Descriptor* d : AllMessages()) {
    for (int i = 0; i < d->field_count(); ++i) {
      ++declared;
      EXPECT_TRUE(pinned.count({d->full_name(), d->field(i)->name()}))
          << d->full_name() << "." << d->field(i)->name()
          << " is not in kFields: verify its number upstream and add it";
    }
  }
  EXPECT_EQ(declared, kFields.size());
}

TEST(SpotProtoEnums, ValuesMatchTheSpotApi) {
  std::set<std::string> pinned;
  for (const auto& spec : kEnums) {
    const std::string name = std::string("bosdyn.api.") + spec.enum_name;
    pinned.insert(name);
    const EnumDescriptor* e = Pool()->FindEnumTypeByName(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_EQ(e->value_count(), static_cast<int>(spec.values.size())) << name;
    for (const auto& [value_name, number] : spec.values) {
      const auto* v = e->FindValueByName(value_name);
      ASSERT_NE(v, nullptr) << name << "." << value_name;
      EXPECT_EQ(v->number(), number) << name << "." << value_name;
    }
  }
  // No enum left unpinned.
  for (const Descriptor* d : AllMessages()) {
    for (int i = 0; i < d->enum_type_count(); ++i) {
      EXPECT_TRUE(pinned.count(d->enum_type(i)->full_name())) << d->enum_type(i)->full_name();
    }
  }
  // And the generated C++ constants agree (these are what the adapter and mock use).
  EXPECT_EQ(api::Image::PIXEL_FORMAT_DEPTH_U16, 5);
  EXPECT_EQ(api::Image::PIXEL_FORMAT_GREYSCALE_U16, 6);
  EXPECT_EQ(api::ImageResponse::STATUS_UNSUPPORTED_PIXEL_FORMAT_REQUESTED, 6);
  EXPECT_EQ(api::GetAuthTokenResponse::STATUS_TEMPORARILY_LOCKED_OUT, 4);
  EXPECT_EQ(api::CommonError::CODE_OK, 1);
}

TEST(SpotProtoServices, MethodNamesMatchTheSpotApi) {
  size_t services = 0;
  for (const auto& [service_name, methods] : kServices) {
    const auto* s = Pool()->FindServiceByName(service_name);
    ASSERT_NE(s, nullptr) << service_name;
    ++services;
    ASSERT_EQ(s->method_count(), static_cast<int>(methods.size())) << service_name;
    for (int i = 0; i < s->method_count(); ++i) {
      const auto* m = s->method(i);
      EXPECT_EQ(m->full_name(), methods[i].full_name);
      EXPECT_EQ(m->input_type()->full_name(), std::string("bosdyn.api.") + methods[i].input);
      EXPECT_EQ(m->output_type()->full_name(), std::string("bosdyn.api.") + methods[i].output);
      EXPECT_FALSE(m->client_streaming()) << m->full_name();
      EXPECT_FALSE(m->server_streaming()) << m->full_name();
    }
  }
  EXPECT_EQ(services, 7u);
  // The generated stubs carry the same names.
  EXPECT_STREQ(api::AuthService::service_full_name(), "bosdyn.api.AuthService");
  EXPECT_STREQ(api::DirectoryService::service_full_name(), "bosdyn.api.DirectoryService");
  EXPECT_STREQ(api::RobotIdService::service_full_name(), "bosdyn.api.RobotIdService");
  EXPECT_STREQ(api::ImageService::service_full_name(), "bosdyn.api.ImageService");
  EXPECT_STREQ(api::PointCloudService::service_full_name(), "bosdyn.api.PointCloudService");
  EXPECT_STREQ(api::RobotStateService::service_full_name(), "bosdyn.api.RobotStateService");
  EXPECT_STREQ(api::TimeSyncService::service_full_name(), "bosdyn.api.TimeSyncService");
}

// ---------------------------------------------------------------------------------------
// Raw bytes of the numbers that matter most.

TEST(SpotWireBytes, ImageCaptureTimeIsField30AndTransformsField31) {
  api::ImageCapture capture;
  capture.mutable_acquisition_time()->set_seconds(1);
  // tag (30 << 3 | 2) = 242 = varint f2 01, length 2, Timestamp{seconds: 1} = 08 01.
  EXPECT_EQ(Hex(capture.SerializeAsString()), "f2 01 02 08 01");
  capture.Clear();
  (*capture.mutable_transforms_snapshot()->mutable_child_to_parent_edge_map())["body"];
  // tag (31 << 3 | 2) = 250 = fa 01.
  EXPECT_EQ(Hex(capture.SerializeAsString().substr(0, 2)), "fa 01");
}

TEST(SpotWireBytes, ImageHasNoField1) {
  EXPECT_EQ(api::Image::descriptor()->FindFieldByNumber(1), nullptr);
  api::Image image;
  image.set_cols(640);
  image.set_rows(480);
  image.set_data("ab");
  image.set_format(api::Image::FORMAT_RAW);
  image.set_pixel_format(api::Image::PIXEL_FORMAT_DEPTH_U16);
  // cols(2)=640, rows(3)=480, data(4)="ab", format(5)=2, pixel_format(6)=5.
  EXPECT_EQ(Hex(image.SerializeAsString()), "10 80 05 18 e0 03 22 02 61 62 28 02 30 05");
  image.set_pixel_format(api::Image::PIXEL_FORMAT_GREYSCALE_U16);
  EXPECT_EQ(Hex(image.SerializeAsString().substr(12)), "30 06");
  // A field-1 varint parses without error and is kept as unknown.
  api::Image parsed;
  ASSERT_TRUE(parsed.ParseFromString(std::string("\x08\x07\x10\x05", 4)));
  EXPECT_EQ(parsed.cols(), 5);
  EXPECT_EQ(parsed.GetReflection()->GetUnknownFields(parsed).field_count(), 1);
}

TEST(SpotWireBytes, ImageResponseStatusIsField4) {
  api::ImageResponse response;
  response.set_status(api::ImageResponse::STATUS_OK);
  EXPECT_EQ(Hex(response.SerializeAsString()), "20 01");
}

TEST(SpotWireBytes, ImageSourceCameraModelsAre8And13And14) {
  api::ImageSource source;
  source.mutable_pinhole();
  EXPECT_EQ(Hex(source.SerializeAsString()), "42 00");
  source.mutable_pinhole_brown_conrady();
  EXPECT_EQ(Hex(source.SerializeAsString()), "6a 00");
  source.mutable_kannala_brandt();
  EXPECT_EQ(Hex(source.SerializeAsString()), "72 00");
  source.Clear();
  source.set_depth_scale(1000.0);  // field 6, fixed64: 31, 1000.0 = 0x408f400000000000
  EXPECT_EQ(Hex(source.SerializeAsString()), "31 00 00 00 00 00 40 8f 40");
}

TEST(SpotWireBytes, ImageRequestFallbackFormatsIsField7) {
  api::ImageRequest request;
  request.add_fallback_formats(api::Image::PIXEL_FORMAT_RGB_U8);
  request.add_fallback_formats(api::Image::PIXEL_FORMAT_GREYSCALE_U8);
  // Packed (proto3 default): tag (7 << 3 | 2) = 3a, length 2, values 03 01.
  EXPECT_EQ(Hex(request.SerializeAsString()), "3a 02 03 01");
}

TEST(SpotWireBytes, GetPointCloudResponsesIsField4) {
  api::GetPointCloudResponse response;
  response.add_point_cloud_responses();
  EXPECT_EQ(Hex(response.SerializeAsString()), "22 00");
}

TEST(SpotWireBytes, PointCloudSourceTimeIsField30) {
  api::PointCloudSource source;
  source.mutable_acquisition_time()->set_seconds(1);
  EXPECT_EQ(Hex(source.SerializeAsString()), "f2 01 02 08 01");
  api::PointCloudResponse response;
  response.mutable_lidar_cloud();
  EXPECT_EQ(Hex(response.SerializeAsString()), "1a 00");
}

TEST(SpotWireBytes, ServiceEntryLivenessTimeoutIsField8) {
  api::ServiceEntry entry;
  entry.set_liveness_timeout_secs(1.5);
  // tag (8 << 3 | 1) = 41, then 1.5 as little-endian IEEE double.
  EXPECT_EQ(Hex(entry.SerializeAsString()), "41 00 00 00 00 00 00 f8 3f");
  entry.Clear();
  entry.set_permission_required("x");
  EXPECT_EQ(Hex(entry.SerializeAsString()), "3a 01 78");  // field 7 (6 is unused upstream)
}

TEST(SpotWireBytes, ResponseHeaderErrorIsField4) {
  api::ResponseHeader header;
  header.mutable_error()->set_code(api::CommonError::CODE_OK);
  EXPECT_EQ(Hex(header.SerializeAsString()), "22 02 08 01");
}

TEST(SpotWireBytes, AuthTokenFields) {
  api::GetAuthTokenRequest request;
  request.set_token("t");
  EXPECT_EQ(Hex(request.SerializeAsString()), "22 01 74");
  api::GetAuthTokenResponse response;
  response.set_status(api::GetAuthTokenResponse::STATUS_TEMPORARILY_LOCKED_OUT);
  response.set_token("t");
  EXPECT_EQ(Hex(response.SerializeAsString()), "10 04 1a 01 74");
}

TEST(SpotWireBytes, RobotStateKinematicStateIsField6) {
  api::RobotState state;
  auto* joint = state.mutable_kinematic_state()->add_joint_states();
  joint->set_name("a");
  joint->mutable_position()->set_value(0.5);
  // RobotState{6: KinematicState{2: JointState{1: "a", 2: DoubleValue{1: 0.5}}}}
  const std::string joint_bytes = "0a 01 61 12 09 09 00 00 00 00 00 00 e0 3f";  // 14 bytes
  EXPECT_EQ(Hex(state.SerializeAsString()), "32 10 12 0e " + joint_bytes);
}

TEST(SpotWireBytes, RobotStateFromARobotSkipsFieldsWeLeftOut) {
  // What a robot sends: power_state (1) and battery_states (2) before kinematic_state (6),
  // and a joint with a velocity (JointState field 3) but no position.
  DoubleValue velocity;
  velocity.set_value(2.0);
  std::string joint = std::string("\x0a\x01h", 3);  // name "h"
  const std::string velocity_bytes = velocity.SerializeAsString();
  joint += '\x1a';  // field 3, length-delimited
  joint += static_cast<char>(velocity_bytes.size());
  joint += velocity_bytes;
  std::string kinematic = "\x12";
  kinematic += static_cast<char>(joint.size());
  kinematic += joint;
  std::string robot = std::string("\x0a\x02\x08\x02", 4) + std::string("\x12\x00", 2);
  robot += '\x32';
  robot += static_cast<char>(kinematic.size());
  robot += kinematic;

  api::RobotState state;
  ASSERT_TRUE(state.ParseFromString(robot));
  ASSERT_EQ(state.kinematic_state().joint_states_size(), 1);
  EXPECT_EQ(state.kinematic_state().joint_states(0).name(), "h");
  EXPECT_FALSE(state.kinematic_state().joint_states(0).has_position());
  // Unknown fields survive a round trip (a proxy or recorder loses nothing).
  EXPECT_EQ(state.SerializeAsString().size(), robot.size());
}

TEST(SpotWireBytes, RoundTripOfAFullImageResponse) {
  api::GetImageResponse response;
  response.mutable_header()->mutable_error()->set_code(api::CommonError::CODE_OK);
  auto* r = response.add_image_responses();
  r->set_status(api::ImageResponse::STATUS_OK);
  auto* shot = r->mutable_shot();
  shot->mutable_acquisition_time()->set_seconds(1700000000);
  shot->mutable_acquisition_time()->set_nanos(5);
  shot->set_frame_name_image_sensor("frontleft_fisheye");
  auto& edges = *shot->mutable_transforms_snapshot()->mutable_child_to_parent_edge_map();
  edges["body"];  // root
  auto& edge = edges["frontleft_fisheye"];
  edge.set_parent_frame_name("body");
  edge.mutable_parent_tform_child()->mutable_position()->set_x(0.4);
  edge.mutable_parent_tform_child()->mutable_rotation()->set_w(1.0);
  shot->mutable_image()->set_cols(640);
  shot->mutable_image()->set_rows(480);
  shot->mutable_image()->set_data(std::string(16, '\x7f'));
  shot->mutable_capture_params()->mutable_exposure_duration()->set_nanos(1000000);
  auto* source = r->mutable_source();
  source->set_name("frontleft_fisheye_image");
  auto* kb = source->mutable_kannala_brandt()->mutable_intrinsics();
  kb->mutable_pinhole_intrinsics()->mutable_focal_length()->set_x(330.0);
  kb->set_k4(-0.01f);

  api::GetImageResponse parsed;
  ASSERT_TRUE(parsed.ParseFromString(response.SerializeAsString()));
  // (Not a byte comparison: map entries serialize in no particular order.)
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(parsed, response));
  const auto& p = parsed.image_responses(0);
  EXPECT_EQ(p.shot().acquisition_time().seconds(), 1700000000);
  EXPECT_EQ(p.shot().transforms_snapshot().child_to_parent_edge_map().at("frontleft_fisheye")
                .parent_frame_name(),
            "body");
  EXPECT_EQ(p.source().camera_models_case(), api::ImageSource::kKannalaBrandt);
  EXPECT_FLOAT_EQ(p.source().kannala_brandt().intrinsics().k4(), -0.01f);
}

// ---------------------------------------------------------------------------------------
// The generated servers answer on /bosdyn.api.<Service>/<Rpc>: call each path by name with a
// generic stub (as a real client's channel would send it) over an in-process channel.

template <class Response>
grpc::Status Answer(const api::RequestHeader& request_header, const char* rpc,
                    Response* response) {
  auto* header = response->mutable_header();
  *header->mutable_request_header() = request_header;
  header->mutable_error()->set_code(api::CommonError::CODE_OK);
  header->mutable_error()->set_message(rpc);
  return grpc::Status::OK;
}

class Auth final : public api::AuthService::Service {
  grpc::Status GetAuthToken(grpc::ServerContext*, const api::GetAuthTokenRequest* q,
                            api::GetAuthTokenResponse* a) override {
    return Answer(q->header(), "GetAuthToken", a);
  }
};
class Directory final : public api::DirectoryService::Service {
  grpc::Status GetServiceEntry(grpc::ServerContext*, const api::GetServiceEntryRequest* q,
                               api::GetServiceEntryResponse* a) override {
    return Answer(q->header(), "GetServiceEntry", a);
  }
  grpc::Status ListServiceEntries(grpc::ServerContext*, const api::ListServiceEntriesRequest* q,
                                  api::ListServiceEntriesResponse* a) override {
    return Answer(q->header(), "ListServiceEntries", a);
  }
};
class RobotId final : public api::RobotIdService::Service {
  grpc::Status GetRobotId(grpc::ServerContext*, const api::RobotIdRequest* q,
                          api::RobotIdResponse* a) override {
    return Answer(q->header(), "GetRobotId", a);
  }
};
class Images final : public api::ImageService::Service {
  grpc::Status ListImageSources(grpc::ServerContext*, const api::ListImageSourcesRequest* q,
                                api::ListImageSourcesResponse* a) override {
    return Answer(q->header(), "ListImageSources", a);
  }
  grpc::Status GetImage(grpc::ServerContext*, const api::GetImageRequest* q,
                        api::GetImageResponse* a) override {
    return Answer(q->header(), "GetImage", a);
  }
};
class PointClouds final : public api::PointCloudService::Service {
  grpc::Status ListPointCloudSources(grpc::ServerContext*,
                                     const api::ListPointCloudSourcesRequest* q,
                                     api::ListPointCloudSourcesResponse* a) override {
    return Answer(q->header(), "ListPointCloudSources", a);
  }
  grpc::Status GetPointCloud(grpc::ServerContext*, const api::GetPointCloudRequest* q,
                             api::GetPointCloudResponse* a) override {
    return Answer(q->header(), "GetPointCloud", a);
  }
};
class RobotState final : public api::RobotStateService::Service {
  grpc::Status GetRobotState(grpc::ServerContext*, const api::RobotStateRequest* q,
                             api::RobotStateResponse* a) override {
    return Answer(q->header(), "GetRobotState", a);
  }
};

class TimeSync final : public api::TimeSyncService::Service {
  grpc::Status TimeSyncUpdate(grpc::ServerContext*, const api::TimeSyncUpdateRequest* q,
                              api::TimeSyncUpdateResponse* a) override {
    return Answer(q->header(), "TimeSyncUpdate", a);
  }
};

class SpotGrpcPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    grpc::ServerBuilder builder;
    builder.RegisterService(&auth_);
    builder.RegisterService(&directory_);
    builder.RegisterService(&robot_id_);
    builder.RegisterService(&images_);
    builder.RegisterService(&point_clouds_);
    builder.RegisterService(&robot_state_);
    builder.RegisterService(&time_sync_);
    server_ = builder.BuildAndStart();
    ASSERT_NE(server_, nullptr);
    channel_ = server_->InProcessChannel(grpc::ChannelArguments());
  }
  void TearDown() override {
    if (server_) server_->Shutdown();
  }

  // Calls `path` by name with a request naming this test as client; returns the status.
  template <class Request, class Response>
  grpc::Status Call(const std::string& path, Response* response) {
    Request request;
    request.mutable_header()->set_client_name("wire_format_test");
    grpc::TemplatedGenericStub<Request, Response> stub(channel_);
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(20));
    grpc::CompletionQueue cq;
    auto call = stub.PrepareUnaryCall(&context, path, request, &cq);
    call->StartCall();
    grpc::Status status;
    call->Finish(response, &status, reinterpret_cast<void*>(1));
    void* tag = nullptr;
    bool ok = false;
    EXPECT_TRUE(cq.Next(&tag, &ok));
    cq.Shutdown();
    while (cq.Next(&tag, &ok)) {
    }
    return status;
  }

  template <class Request, class Response>
  void ExpectAnswered(const std::string& path, const std::string& rpc) {
    Response response;
    const grpc::Status status = Call<Request, Response>(path, &response);
    ASSERT_TRUE(status.ok()) << path << ": " << status.error_code() << " "
                             << status.error_message();
    EXPECT_EQ(response.header().error().message(), rpc) << path;
    EXPECT_EQ(response.header().request_header().client_name(), "wire_format_test") << path;
  }

  Auth auth_;
  Directory directory_;
  RobotId robot_id_;
  Images images_;
  PointClouds point_clouds_;
  RobotState robot_state_;
  TimeSync time_sync_;
  std::unique_ptr<grpc::Server> server_;
  std::shared_ptr<grpc::Channel> channel_;
};

TEST_F(SpotGrpcPaths, EveryRpcAnswersOnItsBosdynApiPath) {
  ExpectAnswered<api::GetAuthTokenRequest, api::GetAuthTokenResponse>(
      "/bosdyn.api.AuthService/GetAuthToken", "GetAuthToken");
  ExpectAnswered<api::GetServiceEntryRequest, api::GetServiceEntryResponse>(
      "/bosdyn.api.DirectoryService/GetServiceEntry", "GetServiceEntry");
  ExpectAnswered<api::ListServiceEntriesRequest, api::ListServiceEntriesResponse>(
      "/bosdyn.api.DirectoryService/ListServiceEntries", "ListServiceEntries");
  ExpectAnswered<api::RobotIdRequest, api::RobotIdResponse>(
      "/bosdyn.api.RobotIdService/GetRobotId", "GetRobotId");
  ExpectAnswered<api::ListImageSourcesRequest, api::ListImageSourcesResponse>(
      "/bosdyn.api.ImageService/ListImageSources", "ListImageSources");
  ExpectAnswered<api::GetImageRequest, api::GetImageResponse>(
      "/bosdyn.api.ImageService/GetImage", "GetImage");
  ExpectAnswered<api::ListPointCloudSourcesRequest, api::ListPointCloudSourcesResponse>(
      "/bosdyn.api.PointCloudService/ListPointCloudSources", "ListPointCloudSources");
  ExpectAnswered<api::GetPointCloudRequest, api::GetPointCloudResponse>(
      "/bosdyn.api.PointCloudService/GetPointCloud", "GetPointCloud");
  ExpectAnswered<api::RobotStateRequest, api::RobotStateResponse>(
      "/bosdyn.api.RobotStateService/GetRobotState", "GetRobotState");
  ExpectAnswered<api::TimeSyncUpdateRequest, api::TimeSyncUpdateResponse>(
      "/bosdyn.api.TimeSyncService/TimeSyncUpdate", "TimeSyncUpdate");
}

TEST_F(SpotGrpcPaths, AWrongPathIsUnimplemented) {
  api::GetImageResponse response;
  EXPECT_EQ((Call<api::GetImageRequest, api::GetImageResponse>(
                 "/bosdyn.api.ImageService/GetImages", &response)
                 .error_code()),
            grpc::StatusCode::UNIMPLEMENTED);
  EXPECT_EQ((Call<api::GetImageRequest, api::GetImageResponse>(
                 "/bosdyn.api.v1.ImageService/GetImage", &response)
                 .error_code()),
            grpc::StatusCode::UNIMPLEMENTED);
}

}  // namespace
