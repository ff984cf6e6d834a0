// Small JSON helpers over protobuf's own JSON support (google.protobuf.Struct), which the
// daemon links anyway: parse a client's message, read its fields with clear errors, and
// write replies.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <google/protobuf/message.h>
#include <google/protobuf/struct.pb.h>

namespace omniview::web::json {

using google::protobuf::Struct;
using google::protobuf::Value;

// A JSON object, or nullopt and `error` (e.g. "not a JSON object: Unexpected token.").
std::optional<Struct> parse_object(std::string_view text, std::string* error);

// Fields of `object`; nullptr when absent. The typed getters throw std::invalid_argument
// naming the field when it is there but of another type (or not a whole number).
const Value* find(const Struct& object, const std::string& key);
std::optional<std::string> string_field(const Struct& object, const std::string& key);
std::optional<double> number_field(const Struct& object, const std::string& key);
std::optional<int64_t> integer_field(const Struct& object, const std::string& key, int64_t lo, int64_t hi);
std::optional<bool> bool_field(const Struct& object, const std::string& key);

// `value` as JSON text (for handing a sub-object to a proto parser).
std::string to_text(const Value& value);
// A protobuf message as proto3 JSON (lowerCamelCase names, enums by name).
std::string message_to_text(const google::protobuf::Message& message);
// Parses proto3 JSON into `message`; unknown fields are errors. "" or an error message.
std::string text_to_message(const std::string& text, google::protobuf::Message& message);

// `s` as a quoted JSON string.
std::string quote(std::string_view s);

}  // namespace omniview::web::json
