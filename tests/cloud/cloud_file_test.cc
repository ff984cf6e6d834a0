// PLY and PCD: round trips in every encoding, files as other tools write them, and clear
// errors for malformed data.
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "core/cloud/cloud_file.h"

namespace omniview {
namespace {

PointCloud sample_cloud(bool all_fields) {
  PointCloud c;
  c.frame = "lidar";
  c.stamp = std::chrono::system_clock::time_point(std::chrono::nanoseconds(1700000000123456789LL));
  for (int i = 0; i < 50; ++i) {
    c.points.emplace_back(0.1f * i, -0.37f * i + 1e-3f, 1.0f / (i + 1));
    if (all_fields) {
      c.rgb.push_back({static_cast<uint8_t>(i * 5), static_cast<uint8_t>(255 - i), static_cast<uint8_t>(i)});
      c.intensity.push_back(0.5f * i);
      c.time.push_back(0.002f * i);
      c.ring.push_back(static_cast<uint16_t>(i % 16));
      c.flags.push_back(static_cast<uint8_t>(i % 8));
      c.camera.push_back(i % 3 == 0 ? kNoCamera : static_cast<uint8_t>(i % 5));
    }
  }
  return c;
}

void expect_same(const PointCloud& a, const PointCloud& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.stamp, b.stamp);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.points[i], b.points[i]) << i;
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.intensity, b.intensity);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.ring, b.ring);
  EXPECT_EQ(a.flags, b.flags);
  EXPECT_EQ(a.camera, b.camera);
}

TEST(CloudFile, PlyRoundTripsInBothEncodings) {
  for (bool all : {false, true}) {
    const auto c = sample_cloud(all);
    expect_same(c, parse_ply(format_ply(c, CloudEncoding::kBinary), "bin.ply"));
    expect_same(c, parse_ply(format_ply(c, CloudEncoding::kAscii), "ascii.ply"));
  }
}

TEST(CloudFile, PcdRoundTripsInBothEncodings) {
  for (bool all : {false, true}) {
    const auto c = sample_cloud(all);
    expect_same(c, parse_pcd(format_pcd(c, CloudEncoding::kBinary), "bin.pcd"));
    expect_same(c, parse_pcd(format_pcd(c, CloudEncoding::kAscii), "ascii.pcd"));
  }
}

TEST(CloudFile, FilesOnDiskByContentAndExtension) {
  const auto dir = std::filesystem::temp_directory_path() / ("omniview_cloud_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto c = sample_cloud(true);
  save_cloud(c, (dir / "a.ply").string());
  save_cloud(c, (dir / "a.pcd").string(), CloudEncoding::kAscii);
  expect_same(c, load_cloud((dir / "a.ply").string()));
  expect_same(c, load_cloud((dir / "a.pcd").string()));
  EXPECT_THROW(save_cloud(c, (dir / "a.xyz").string()), std::runtime_error);
  try {
    load_cloud((dir / "missing.ply").string());
    FAIL();
  } catch (const CloudFormatError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ply"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST(CloudFile, PlyAsMeshToolsWriteIt) {
  // Big-endian doubles, float colours, a face list before the vertices, extra properties.
  std::string ply =
      "ply\r\nformat binary_big_endian 1.0\r\ncomment made by hand\r\nelement face 1\r\n"
      "property list uchar int vertex_indices\r\nelement vertex 2\r\nproperty double x\r\n"
      "property double y\r\nproperty double z\r\nproperty float nx\r\nproperty float red\r\n"
      "property float green\r\nproperty float blue\r\nend_header\r\n";
  auto be = [&](auto v) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    for (int i = sizeof v - 1; i >= 0; --i) ply.push_back(b[i]);
  };
  ply.push_back(3);
  be(int32_t{0}); be(int32_t{1}); be(int32_t{1});
  be(1.5); be(-2.0); be(3.25); be(0.f); be(1.f); be(0.5f); be(0.f);
  be(4.0); be(5.0); be(6.0); be(0.f); be(0.f); be(0.f); be(1.f);
  const auto c = parse_ply(ply, "mesh.ply");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.points[0], Eigen::Vector3f(1.5f, -2.f, 3.25f));
  EXPECT_EQ(c.points[1], Eigen::Vector3f(4.f, 5.f, 6.f));
  EXPECT_EQ(c.rgb[0], (PointCloud::Rgb{255, 128, 0}));
  EXPECT_EQ(c.rgb[1], (PointCloud::Rgb{0, 0, 255}));
}

TEST(CloudFile, PcdAsPclWritesIt) {
  // Packed rgb as a float (PCL's ASCII), a padding field with COUNT 3, no COUNT line.
  const std::string pcd =
      "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb _\nSIZE 4 4 4 4 1\n"
      "TYPE F F F F U\nCOUNT 1 1 1 1 3\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n"
      "1 2 3 4.2108e+06 0 0 0\nnan nan nan 0 1 2 3\n";
  const auto c = parse_pcd(pcd, "pcl.pcd");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.points[0], Eigen::Vector3f(1, 2, 3));
  EXPECT_TRUE(std::isnan(c.points[1].x()));
  // 4.2108e+06 is the float whose bits are 0x4A808080 ~ packed (128, 128, 128) in PCL's
  // tutorials; check the bits decode as PCL would.
  const float f = 4.2108e+06f;
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  EXPECT_EQ(c.rgb[0], (PointCloud::Rgb{uint8_t(bits >> 16), uint8_t(bits >> 8), uint8_t(bits)}));
}

std::string error_of(const std::string& data, bool ply) {
  try {
    if (ply) parse_ply(data, "bad.ply"); else parse_pcd(data, "bad.pcd");
  } catch (const CloudFormatError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(CloudFile, MalformedPlyNamesFileAndField) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  EXPECT_EQ(error_of("plx\n", true), "bad.ply: not a PLY file (the first line must be 'ply')");
  EXPECT_NE(error_of(head + "1 2 3\n4 five 6\n", true).find("property 'y': 'five' is not a valid value"), std::string::npos);
  EXPECT_NE(error_of(head + "1 2 3\n4 5\n", true).find("data ends in element 'vertex' 1 of 2, property 'z'"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n", true)
                .find("bad.ply: element 'vertex': no point field(s) z"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat binary_little_endian 1.0\nelement vertex 1000000\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\nabc", true)
                .find("declares 1000000 records of 12 bytes, but only 3 bytes follow"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", true).find("unknown type 'quad'"),
            std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\n", true).find("no 'end_header'"), std::string::npos);
  EXPECT_NE(error_of("ply\nformat ascii 1.0\nelement vertex 1\nproperty uchar red\nend_header\n300\n", true).find("no point field"),
            std::string::npos);
}

TEST(CloudFile, MalformedPcdNamesFileAndField) {
  const std::string head = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  EXPECT_NE(error_of(head + "DATA ascii\n1 2 3\n4 x 6\n", false).find("point 1, field 'y': 'x' is not a valid value"),
            std::string::npos);
  EXPECT_NE(error_of(head + "DATA binary\n12345", false).find("POINTS 2 of 12 bytes need more"), std::string::npos);
  EXPECT_NE(error_of(head + "DATA binary_compressed\n", false).find("binary_compressed is not supported"), std::string::npos);
  EXPECT_NE(error_of("VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nPOINTS 1\nDATA ascii\n", false)
                .find("SIZE lists 2 sizes for 3 FIELDS"), std::string::npos);
  EXPECT_NE(error_of("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 3\nTYPE F F F\nPOINTS 1\nDATA ascii\n", false)
                .find("field 'z': TYPE F with SIZE 3 is not a valid pair"), std::string::npos);
  EXPECT_NE(error_of("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nHEIGHT 1\nPOINTS 2\nDATA ascii\n", false)
                .find("POINTS 2 differs from WIDTH x HEIGHT = 3"), std::string::npos);
  EXPECT_NE(error_of("VERSION 0.7\nFIELDS x y z\n", false).find("header ends before its DATA line"), std::string::npos);
}

// A reader given a limit refuses a header that declares more points, before its body: a
// 21 M-point file was parsed whole before omniview render refused it.
TEST(CloudFile, AHeaderDeclaringTooManyPointsIsRefusedBeforeItsBody) {
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n1 2 3\n4 5 6\n7 8 9\n";
  // The message a parse ends with ("" when it ends without one).
  const auto refusal = [](auto parse) -> std::string {
    try {
      parse();
    } catch (const CloudFormatError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(parse_ply(ply, "a.ply", 3).size(), 3u);
  EXPECT_EQ(refusal([&] { parse_ply(ply, "a.ply", 2); }), "a.ply: its header declares 3 points, more than the limit of 2");
  // The body is never looked at: a header alone is enough to refuse.
  EXPECT_THROW(parse_ply("ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                         "property float y\nproperty float z\nend_header\n",
                         "b.ply", 20'000'000),
               CloudFormatError);
  const std::string pcd = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 3\nHEIGHT 1\n"
                          "POINTS 3\nDATA ascii\n1 2 3\n4 5 6\n7 8 9\n";
  EXPECT_EQ(parse_pcd(pcd, "a.pcd", 3).size(), 3u);
  EXPECT_EQ(refusal([&] { parse_pcd(pcd, "a.pcd", 2); }), "a.pcd: its header declares 3 points, more than the limit of 2");
}

TEST(CloudFile, FilterAndAppendKeepFieldsTogether) {
  auto c = sample_cloud(true);
  std::vector<bool> keep(c.size());
  for (size_t i = 0; i < keep.size(); ++i) keep[i] = i % 2 == 0;
  c.filter(keep);
  ASSERT_EQ(c.size(), 25u);
  EXPECT_EQ(c.ring[1], 2);
  auto later = sample_cloud(true);
  later.stamp += std::chrono::milliseconds(100);
  c.append(later);
  ASSERT_EQ(c.size(), 75u);
  EXPECT_NEAR(c.time[25], 0.1f, 1e-6f);
  EXPECT_NO_THROW(c.check("c"));
}

}  // namespace
}  // namespace omniview
