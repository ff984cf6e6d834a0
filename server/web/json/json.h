// Small JSON helpers for the web endpoint: parse a client's message, read its fields with
// clear errors, and write replies. Client JSON goes through nlohmann::json (header-only,
// so it is compiled with the rest of the daemon, sanitizers included); API messages go to
// and from proto3 JSON through protobuf's own converter.
//
// Not google.protobuf.Struct: its map lives in the uninstrumented libprotobuf, whose
// MapFieldBase has another layout than ThreadSanitizer's build of the same header.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <google/protobuf/message.h>
#include <nlohmann/json.hpp>

namespace omniview::web::json {

using Value = nlohmann::json;

// Objects and arrays nested deeper than any client message needs are refused (as the
// proto3 JSON parser refuses them).
inline constexpr int kMaxDepth = 100;

// A JSON object, or nullopt and `error` (e.g. "not a JSON object: syntax error ...").
std::optional<Value> parse_object(std::string_view text, std::string* error);

// Fields of the object `object`; nullptr when absent. The typed getters treat null as
// absent and throw std::invalid_argument naming the field when it is there but of another
// type (or not a whole number in range).
const Value* find(const Value& object, const std::string& key);
std::optional<std::string> string_field(const Value& object, const std::string& key);
std::optional<double> number_field(const Value& object, const std::string& key);
std::optional<int64_t> integer_field(const Value& object, const std::string& key, int64_t lo, int64_t hi);
std::optional<bool> bool_field(const Value& object, const std::string& key);

// `value` as compact JSON text (for handing a sub-object to a proto parser).
std::string to_text(const Value& value);
// A protobuf message as proto3 JSON (lowerCamelCase names, enums by name).
std::string message_to_text(const google::protobuf::Message& message);
// Parses proto3 JSON into `message`; unknown fields are errors. "" or an error message.
std::string text_to_message(const std::string& text, google::protobuf::Message& message);

// `s` as a quoted JSON string.
std::string quote(std::string_view s);

}  // namespace omniview::web::json
