// The schema of a protobuf channel as Foxglove's tools take it (the WebSocket protocol's
// `schema` in base64, an MCAP Schema record's data as is): the serialized
// google.protobuf.FileDescriptorSet of the message's file and everything it imports,
// dependencies first. Shared by the Foxglove WebSocket endpoint and the MCAP export.
#pragma once

#include <string>

#include <google/protobuf/descriptor.h>

namespace omniview::foxglove_schema {

std::string descriptor_set(const google::protobuf::Descriptor* message_type);

}  // namespace omniview::foxglove_schema
