#include "server/web/json/json.h"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <google/protobuf/util/json_util.h>

namespace omniview::web::json {

namespace util = google::protobuf::util;

namespace {

// nlohmann's messages start with "[json.exception.parse_error.101] ": clients need the rest.
std::string without_exception_tag(const std::string& what) {
  const auto end = what.find("] ");
  return what.rfind("[json.exception.", 0) == 0 && end != std::string::npos ? what.substr(end + 2) : what;
}

}  // namespace

std::optional<Value> parse_object(std::string_view text, std::string* error) {
  const auto refuse = [error](const std::string& why) {
    if (error) *error = "not a JSON object: " + why;
    return std::nullopt;
  };
  int depth = 0;  // the most objects and arrays open at once
  const auto deepest = [&depth](int d, Value::parse_event_t event, Value&) {
    using Event = Value::parse_event_t;
    if (event == Event::object_start || event == Event::array_start) depth = std::max(depth, d + 1);
    return true;
  };
  Value value;
  try {
    value = Value::parse(text.begin(), text.end(), deepest);  // comments are errors too
  } catch (const Value::exception& e) {
    // Every kind nlohmann throws while parsing, not only parse_error: a number beyond
    // double's range ("1e400") is an out_of_range, and once ended the daemon (issue 33).
    return refuse(without_exception_tag(e.what()));
  }
  if (!value.is_object()) return refuse(std::string("the message is a JSON ") + value.type_name());
  if (depth > kMaxDepth) return refuse("nested deeper than " + std::to_string(kMaxDepth) + " levels");
  return value;
}

const Value* find(const Value& object, const std::string& key) {
  if (!object.is_object()) return nullptr;
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::optional<std::string> string_field(const Value& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->is_null()) return std::nullopt;
  if (!v->is_string()) throw std::invalid_argument("'" + key + "' must be a string");
  return v->get<std::string>();
}

std::optional<double> number_field(const Value& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->is_null()) return std::nullopt;
  if (!v->is_number() || !std::isfinite(v->get<double>())) {
    throw std::invalid_argument("'" + key + "' must be a number");
  }
  return v->get<double>();
}

std::optional<int64_t> integer_field(const Value& object, const std::string& key, int64_t lo, int64_t hi) {
  const auto n = number_field(object, key);
  if (!n) return std::nullopt;
  if (*n != std::floor(*n) || *n < static_cast<double>(lo) || *n > static_cast<double>(hi)) {
    throw std::invalid_argument("'" + key + "' must be a whole number from " + std::to_string(lo) + " to " +
                                std::to_string(hi));
  }
  return static_cast<int64_t>(*n);
}

std::optional<bool> bool_field(const Value& object, const std::string& key) {
  const Value* v = find(object, key);
  if (!v || v->is_null()) return std::nullopt;
  if (!v->is_boolean()) throw std::invalid_argument("'" + key + "' must be true or false");
  return v->get<bool>();
}

std::string to_text(const Value& value) { return value.dump(); }

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
