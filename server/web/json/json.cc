#include "server/web/json/json.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <google/protobuf/util/json_util.h>

namespace omniview::web::json {

namespace util = google::protobuf::util;

std::optional<Struct> parse_object(std::string_view text, std::string* error) {
  Struct object;
  util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  const auto status = util::JsonStringToMessage(std::string(text), &object, options);
  if (!status.ok()) {
    if (error) *error = "not a JSON object: " + std::string(status.message());
    return std::nullopt;
  }
  return object;
}

const Value* find(const Struct& object, const std::string& key) {
  const auto it = object.fields().find(key);
  return it == object.fields().end() ? nullptr : &it->second;
}

std::optional<std::string> string_field(const Struct& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->has_null_value()) return std::nullopt;
  if (!v->has_string_value()) throw std::invalid_argument("'" + key + "' must be a string");
  return v->string_value();
}

std::optional<double> number_field(const Struct& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->has_null_value()) return std::nullopt;
  if (!v->has_number_value() || !std::isfinite(v->number_value())) {
    throw std::invalid_argument("'" + key + "' must be a number");
  }
  return v->number_value();
}

std::optional<int64_t> integer_field(const Struct& object, const std::string& key, int64_t lo, int64_t hi) {
  const auto n = number_field(object, key);
  if (!n) return std::nullopt;
  if (*n != std::floor(*n) || *n < static_cast<double>(lo) || *n > static_cast<double>(hi)) {
    throw std::invalid_argument("'" + key + "' must be a whole number from " + std::to_string(lo) + " to " +
                                std::to_string(hi));
  }
  return static_cast<int64_t>(*n);
}

std::optional<bool> bool_field(const Struct& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->has_null_value()) return std::nullopt;
  if (!v->has_bool_value()) throw std::invalid_argument("'" + key + "' must be true or false");
  return v->bool_value();
}

std::string to_text(const Value& value) {
  std::string out;
  (void)util::MessageToJsonString(value, &out);
  return out;
}

std::string message_to_text(const google::protobuf::Message& message) {
  std::string out;
  util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;  // a client reads `valid: false`, not a missing key
  const auto status = util::MessageToJsonString(message, &out, options);
  if (!status.ok()) throw std::runtime_error("cannot write JSON: " + std::string(status.message()));
  return out;
}

std::string text_to_message(const std::string& text, google::protobuf::Message& message) {
  util::JsonParseOptions options;
  options.ignore_unknown_fields = false;  // a misspelt field is an error, never silently nothing
  const auto status = util::JsonStringToMessage(text, &message, options);
  return status.ok() ? "" : std::string(status.message());
}

std::string quote(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

}  // namespace omniview::web::json
