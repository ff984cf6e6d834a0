// YamlReader: typed reads and poses, with messages that name file, line and key path.
#include "core/io/yaml_reader.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"

namespace omniview {
namespace {

using testing::expect_throw_containing;
using testing::kDeg;

YamlReader doc(const std::string& text) { return YamlReader::from_string(text, "conf.yaml"); }

TEST(YamlReader, ReadsTypedValues) {
  const auto r = doc("a: 1.5\nb: 7\nc: hello\nd: true\ne: [1, 2.5, -3e2]\n");
  EXPECT_EQ(r.number(r.root()["a"], "a"), 1.5);
  EXPECT_EQ(r.integer(r.root()["b"], "b"), 7);
  EXPECT_EQ(r.text(r.root()["c"], "c"), "hello");
  EXPECT_TRUE(r.boolean(r.root()["d"], "d"));
  EXPECT_EQ(r.numbers(r.root()["e"], "e"), (std::vector<double>{1, 2.5, -300}));
  EXPECT_EQ(r.numbers(r.root()["e"], "e", 3).size(), 3u);
  EXPECT_EQ(r.file(), "conf.yaml");
}

TEST(YamlReader, WrongTypesNameFileLineAndPath) {
  const auto r = doc("a: 1\nb: [1, 2]\nc: x1\nd: maybe\ne: [1, .nan]\nf: .inf\ng: 2.5\nh: {k: 1}\n");
  expect_throw_containing<ConfigError>([&] { r.number(r.root()["c"], "cams[0].c"); },
                                       {"conf.yaml:3: cams[0].c: expected a number, got 'x1'"});
  expect_throw_containing<ConfigError>([&] { r.number(r.root()["b"], "b"); }, {"conf.yaml:2: b: expected a number"});
  expect_throw_containing<ConfigError>([&] { r.integer(r.root()["g"], "g"); }, {"conf.yaml:7: g: expected an integer"});
  expect_throw_containing<ConfigError>([&] { r.boolean(r.root()["d"], "d"); },
                                       {"conf.yaml:4: d: expected true or false"});
  expect_throw_containing<ConfigError>([&] { r.text(r.root()["h"], "h"); }, {"conf.yaml:8: h: expected a string"});
  expect_throw_containing<ConfigError>([&] { r.numbers(r.root()["a"], "a"); }, {"conf.yaml:1: a: expected a list"});
  expect_throw_containing<ConfigError>([&] { r.numbers(r.root()["e"], "e"); }, {"conf.yaml:5: e[1]: must be finite"});
  expect_throw_containing<ConfigError>([&] { r.number(r.root()["f"], "f"); }, {"conf.yaml:6: f: must be finite"});
  expect_throw_containing<ConfigError>([&] { r.numbers(r.root()["b"], "b", 3); },
                                       {"conf.yaml:2: b: expected 3 numbers, got 2"});
}

TEST(YamlReader, KeysAreCheckedForTyposAndDuplicates) {
  const auto r = doc("cam:\n  name: a\n  intrinsincs: [1]\n");
  expect_throw_containing<ConfigError>(
      [&] {
        r.expect_keys(r.root()["cam"], "cameras[0]", {"name", "intrinsics"});
      },
      {"conf.yaml:3: cameras[0].intrinsincs: unknown key", "name, intrinsics"});
  // yaml-cpp keeps both copies of a repeated key and returns the first: an edit to the
  // second would silently do nothing.
  const auto dup = doc("cam:\n  name: a\n  fov_deg: 190\n  fov_deg: 200\n");
  expect_throw_containing<ConfigError>(
      [&] {
        dup.expect_keys(dup.root()["cam"], "cam", {"name", "fov_deg"});
      },
      {"conf.yaml:4: cam.fov_deg: key given twice (first on line 3)"});
  EXPECT_NO_THROW(r.expect_keys(doc("x: 1\ny: 2\n").root(), "", {"x", "y", "z"}));
  expect_throw_containing<ConfigError>([&] { r.expect_keys(r.root()["cam"]["name"], "cam.name", {"x"}); },
                                       {"cam.name: expected a map"});
}

TEST(YamlReader, MissingRequiredKeyNamesTheMapAndKey) {
  const auto r = doc("top: 1\ncams:\n  - name: a\n    res: [1, 2]\n  - name: b\n    model:\n");
  expect_throw_containing<ConfigError>([&] { r.required(r.root()["cams"][0], "model", "cams[0] (a)"); },
                                       {"conf.yaml:3: cams[0] (a): missing required key 'model'"});
  // A key with no value counts as missing.
  expect_throw_containing<ConfigError>([&] { r.required(r.root()["cams"][1], "model", "cams[1]"); },
                                       {"conf.yaml:5: cams[1]: missing required key 'model'"});
  EXPECT_EQ(r.text(r.required(r.root()["cams"][0], "name", "cams[0]"), "name"), "a");
}

TEST(YamlReader, SyntaxErrorsAndMissingFiles) {
  expect_throw_containing<ConfigError>([] { doc("a: [1, 2\nb: 3\n"); }, {"conf.yaml:", "YAML syntax error"});
  expect_throw_containing<ConfigError>([] { doc("a: 1\n  b: 2\n"); }, {"conf.yaml:2", "YAML syntax error"});
  testing::TempDir dir;
  expect_throw_containing<ConfigError>([&] { YamlReader::from_file(dir / "absent.yaml"); },
                                       {dir / "absent.yaml", "cannot open file"});
  // A folder opens as an empty stream; say what it is rather than "expected a map".
  expect_throw_containing<ConfigError>([&] { YamlReader::from_file(dir.path().string()); }, {"is a directory"});
  const auto r = YamlReader::from_file(dir.write("ok.yaml", "a: 2\n"));
  EXPECT_EQ(r.file(), dir / "ok.yaml");
  EXPECT_EQ(r.number(r.root()["a"], "a"), 2);
}

TEST(YamlReader, PoseFromKalibrMatrix) {
  const auto r =
      doc("T:\n"
          "  - [0.0, -1.0, 0.0, 0.1]\n"
          "  - [1.0, 0.0, 0.0, 0.2]\n"
          "  - [0.0, 0.0, 1.0, 0.3]\n"
          "  - [0.0, 0.0, 0.0, 1.0]\n");
  const Pose T = r.pose(r.root()["T"], "T");
  EXPECT_TRUE(T.translation().isApprox(Vec3(0.1, 0.2, 0.3)));
  EXPECT_TRUE((T.linear() * Vec3::UnitX()).isApprox(Vec3::UnitY()));
}

TEST(YamlReader, PoseFromXyzAndAngles) {
  const auto r =
      doc("a: {xyz: [1, 2, 3], ypr_deg: [90, 30, -10]}\n"
          "b: {xyz: [1, 2, 3], quat_xyzw: [0, 0, 0.7071067811865476, 0.7071067811865476]}\n"
          "c: {xyz: [4, 5, 6]}\n"
          "d: {ypr_deg: [0, 90, 0]}\n");
  const Pose a = r.pose(r.root()["a"], "a");
  EXPECT_TRUE(a.translation().isApprox(Vec3(1, 2, 3)));
  EXPECT_TRUE(a.linear().isApprox(rotation_from_ypr(90 * kDeg, 30 * kDeg, -10 * kDeg), 1e-12));
  const Pose b = r.pose(r.root()["b"], "b");  // 90 deg about z
  EXPECT_TRUE(b.linear().isApprox(rotation_from_ypr(90 * kDeg, 0, 0), 1e-12));
  EXPECT_TRUE(r.pose(r.root()["c"], "c").linear().isApprox(Mat3::Identity()));
  EXPECT_TRUE(r.pose(r.root()["c"], "c").translation().isApprox(Vec3(4, 5, 6)));
  EXPECT_TRUE((r.pose(r.root()["d"], "d").linear() * Vec3::UnitX()).isApprox(-Vec3::UnitZ(), 1e-12));
}

TEST(YamlReader, BadPosesNameLineAndKey) {
  const auto r =
      doc("scaled:\n"
          "  - [2, 0, 0, 0]\n"
          "  - [0, 1, 0, 0]\n"
          "  - [0, 0, 1, 0]\n"
          "  - [0, 0, 0, 1]\n"
          "rows: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]\n"
          "short_row: [[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
          "both: {xyz: [0, 0, 0], ypr_deg: [0, 0, 0], quat_xyzw: [0, 0, 0, 1]}\n"
          "quat: {quat_xyzw: [0, 0, 0, 2]}\n"
          "typo: {xzy: [0, 0, 0]}\n"
          "scalar: 5\n");
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["scaled"], "cam1.T_cn_cnm1"); },
                                       {"conf.yaml:2: ", "cam1.T_cn_cnm1", "not a rotation"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["rows"], "rows"); },
                                       {"conf.yaml:6: rows", "4 rows, got 3"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["short_row"], "T"); },
                                       {"conf.yaml:7: T[1]: expected 4 numbers, got 3"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["both"], "both"); }, {"conf.yaml:8: both", "not both"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["quat"], "quat"); },
                                       {"conf.yaml:9: quat.quat_xyzw", "unit length"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["typo"], "typo"); },
                                       {"conf.yaml:10: typo.xzy: unknown key"});
  expect_throw_containing<ConfigError>([&] { r.pose(r.root()["scalar"], "scalar"); }, {"conf.yaml:11: scalar", "4x4"});
}

}  // namespace
}  // namespace omniview
