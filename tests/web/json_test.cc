// The endpoint's JSON helpers (server/web/json): what a client's message may be, and the
// errors that name what is wrong with it.
#include <gtest/gtest.h>

#include <string>

#include "server/web/json/json.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview::web {
namespace {

json::Value object(const std::string& text) {
  std::string error;
  auto value = json::parse_object(text, &error);
  EXPECT_TRUE(value) << text << ": " << error;
  return value ? *value : json::Value::object();
}

std::string refusal(const std::string& text) {
  std::string error;
  EXPECT_FALSE(json::parse_object(text, &error)) << text;
  return error;
}

TEST(Json, OnlyObjectsAreMessages) {
  EXPECT_NE(refusal("{not json").find("not a JSON object: "), std::string::npos);
  EXPECT_EQ(refusal("[1, 2]"), "not a JSON object: the message is a JSON array");
  EXPECT_NE(refusal("").find("not a JSON object"), std::string::npos);
  EXPECT_NE(refusal("{} {}").find("not a JSON object"), std::string::npos);    // trailing text
  EXPECT_NE(refusal("{/* c */}").find("not a JSON object"), std::string::npos);  // no comments
  EXPECT_NE(refusal("{\"a\": \"\xff\"}").find("not a JSON object"), std::string::npos);  // not UTF-8
  const std::string deep = std::string(json::kMaxDepth, '[') + std::string(json::kMaxDepth, ']');
  EXPECT_NE(refusal("{\"a\":" + deep + "}").find("nested deeper"), std::string::npos);
  EXPECT_TRUE(object("{\"a\":" + std::string(json::kMaxDepth - 2, '[') + std::string(json::kMaxDepth - 2, ']') + "}")
                  .contains("a"));
}

// Numbers beyond double's range throw out_of_range inside nlohmann's parser, not a
// parse_error: it once escaped every handler and ended the daemon before any token.
TEST(Json, NumbersBeyondDoubleRangeAreRefusedNotThrown) {
  for (const char* text : {R"({"op": 1e400})", R"({"a": -1e309})", R"({"a": {"b": [1, 1e400]}})", "{\"id\": 1e99999}"}) {
    EXPECT_NE(refusal(text).find("not a JSON object: "), std::string::npos) << text;
  }
  EXPECT_EQ(object(R"({"a": 1.7e308})")["a"], 1.7e308);  // the largest doubles still parse
}

TEST(Json, TypedFieldsNameTheFieldThatIsWrong) {
  const auto m = object(R"({"s": "x", "n": 2.5, "i": 7, "b": true, "z": null, "big": 1e300})");
  EXPECT_EQ(json::string_field(m, "s"), "x");
  EXPECT_EQ(json::number_field(m, "n"), 2.5);
  EXPECT_EQ(json::integer_field(m, "i", 0, 10), 7);
  EXPECT_EQ(json::bool_field(m, "b"), true);
  EXPECT_FALSE(json::string_field(m, "z"));  // null reads as absent
  EXPECT_FALSE(json::number_field(m, "missing"));
  EXPECT_THROW(json::string_field(m, "n"), std::invalid_argument);
  EXPECT_THROW(json::bool_field(m, "s"), std::invalid_argument);
  try {
    json::integer_field(m, "n", 0, 10);
    FAIL() << "2.5 is no whole number";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "'n' must be a whole number from 0 to 10");
  }
  EXPECT_THROW(json::integer_field(m, "i", 0, 5), std::invalid_argument);
  EXPECT_THROW(json::integer_field(m, "big", 0, 5), std::invalid_argument);
  EXPECT_THROW(json::number_field(object(R"({"n": "1"})"), "n"), std::invalid_argument);
  EXPECT_FALSE(json::string_field(object("{}"), "s"));
}

TEST(Json, SubObjectsReachProtoMessages) {
  const auto m = object(R"({"request": {"name": "front", "set": {"hfovDeg": 90.5}}})");
  v1::UpdateViewRequest request;
  EXPECT_EQ(json::text_to_message(json::to_text(*json::find(m, "request")), request), "");
  EXPECT_EQ(request.name(), "front");
  EXPECT_EQ(request.set().hfov_deg(), 90.5);
  v1::GetViewRequest misspelt;
  EXPECT_NE(json::text_to_message(R"({"nmae": "front"})", misspelt), "");
  // A map field both ways (SetJointPositions), which proto3 JSON converts through reflection.
  v1::SetJointPositionsRequest joints;
  ASSERT_EQ(json::text_to_message(R"({"positions": {"arm0.sh0": 0.5}})", joints), "");
  EXPECT_EQ(joints.positions().at("arm0.sh0"), 0.5);
  EXPECT_NE(json::message_to_text(joints).find("\"arm0.sh0\":0.5"), std::string::npos);
}

TEST(Json, QuoteEscapesWhatJsonMust) {
  EXPECT_EQ(json::quote("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\n\\u0001\"");
  EXPECT_EQ(json::quote("grüße"), "\"grüße\"");
  const auto round = object("{\"s\":" + json::quote("tab\there \x1f") + "}");
  EXPECT_EQ(json::string_field(round, "s"), "tab\there \x1f");
}

}  // namespace
}  // namespace omniview::web
