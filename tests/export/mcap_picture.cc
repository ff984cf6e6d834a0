// mcap-picture FILE.mcap OUT.jpg: one picture of what an exported MCAP file holds, made
// with the project's own reader (core/mcap) and the tests' H.264 decoder (libavcodec), for
// the README (Foxglove and Lichtblick are not in Debian). Top: each view's picture at the
// middle of the file (its H.264 decoded from the key frame before), a camera's image and
// the coloured cloud from above; below: the timeline, one row per topic, a tick per message,
// as a player's timeline shows them. A development tool: not installed, not in the product.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/io/image_codec.h"
#include "core/mcap/mcap_reader.h"
#include "foxglove/omniview_schemas.pb.h"
#include "tests/video/h264_decoder.h"

namespace omniview {
namespace {

const cv::Scalar kInk(235, 235, 235), kDim(150, 150, 150), kAccent(80, 180, 255);
constexpr int kPictureHeight = 240;

void label(cv::Mat& canvas, const std::string& text, cv::Point at, double scale = 0.5, cv::Scalar colour = kInk) {
  cv::putText(canvas, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

// `picture` scaled to fit `box` on the canvas, with its topic above.
void place(cv::Mat& canvas, const cv::Mat& picture, cv::Rect box, const std::string& title) {
  label(canvas, title, {box.x, box.y - 8});
  if (picture.empty()) return;
  cv::Mat bgr = picture;
  if (bgr.channels() == 1) cv::cvtColor(bgr, bgr, cv::COLOR_GRAY2BGR);
  const double s = std::min(double(box.width) / bgr.cols, double(box.height) / bgr.rows);
  cv::Mat scaled;
  cv::resize(bgr, scaled, {}, s, s, cv::INTER_AREA);
  scaled.copyTo(canvas(cv::Rect(box.x, box.y, scaled.cols, scaled.rows)));
}

// The coloured cloud from above, 5 m around the robot.
cv::Mat cloud_from_above(const foxglove::PointCloud& cloud, int size) {
  cv::Mat out(size, size, CV_8UC3, cv::Scalar(25, 25, 25));
  std::map<std::string, uint32_t> at;
  for (const auto& f : cloud.fields()) at[f.name()] = f.offset();
  if (!at.count("x") || !at.count("y") || cloud.point_stride() == 0) return out;
  const bool rgb = at.count("red") && at.count("green") && at.count("blue");
  const double metres = 5;
  for (size_t off = 0; off + cloud.point_stride() <= cloud.data().size(); off += cloud.point_stride()) {
    const char* p = cloud.data().data() + off;
    float x, y;
    std::memcpy(&x, p + at["x"], 4);
    std::memcpy(&y, p + at["y"], 4);
    const int u = static_cast<int>(size / 2 - y / metres * size / 2), v = static_cast<int>(size / 2 - x / metres * size / 2);
    if (u < 0 || v < 0 || u >= size || v >= size) continue;
    cv::Vec3b c(200, 200, 200);
    if (rgb) c = cv::Vec3b(uint8_t(p[at["blue"]]), uint8_t(p[at["green"]]), uint8_t(p[at["red"]]));
    cv::circle(out, {u, v}, 1, cv::Scalar(c[0], c[1], c[2]), cv::FILLED);
  }
  return out;
}

int run(const std::string& file, const std::string& out_path) {
  const mcap::McapContents mcap = mcap::read_mcap_file(file);
  if (mcap.messages.empty()) throw std::runtime_error(file + ": no messages");
  uint64_t t0 = UINT64_MAX, t1 = 0;
  for (const auto& m : mcap.messages) {
    t0 = std::min(t0, m.log_time);
    t1 = std::max(t1, m.log_time);
  }
  const uint64_t middle = t0 + (t1 - t0) / 2;
  const auto schema_of = [&](const mcap::MessageInfo& m) {
    return mcap.schemas.at(mcap.channels.at(m.channel).schema_id).name;
  };
  // Per topic: its messages' times, and its picture at the middle.
  std::map<std::string, std::vector<uint64_t>> times;
  std::map<std::string, cv::Mat> pictures;
  std::map<std::string, std::unique_ptr<testing::H264Decoder>> decoders;
  foxglove::PointCloud middle_cloud;
  for (const auto& m : mcap.messages) {
    const std::string& topic = mcap.channels.at(m.channel).topic;
    times[topic].push_back(m.log_time);
    if (m.log_time > middle) continue;
    const std::string schema = schema_of(m);
    if (schema == "foxglove.CompressedVideo") {
      foxglove::CompressedVideo v;
      v.ParseFromString(m.data);
      auto& decoder = decoders[topic];
      if (!decoder) decoder = std::make_unique<testing::H264Decoder>();
      const cv::Mat i420 = decoder->decode(v.data());
      if (!i420.empty()) cv::cvtColor(i420, pictures[topic], cv::COLOR_YUV2BGR_I420);
    } else if (schema == "foxglove.CompressedImage") {
      foxglove::CompressedImage c;
      c.ParseFromString(m.data);
      pictures[topic] = decode_image(c.data());
    } else if (schema == "foxglove.PointCloud") {
      middle_cloud.ParseFromString(m.data);
    }
  }
  cv::Mat canvas(760, 1400, CV_8UC3, cv::Scalar(32, 32, 32));
  char head[256];
  std::snprintf(head, sizeof head, "%s: %.1f s, %zu messages on %zu topics; pictures at %.1f s", file.c_str(),
                (t1 - t0) / 1e9, mcap.messages.size(), times.size(), (middle - t0) / 1e9);
  label(canvas, head, {20, 30}, 0.6);
  int x = 20;
  for (const auto& [topic, picture] : pictures) {
    if (topic.rfind("/views/", 0) != 0) continue;
    const double aspect = double(picture.cols) / picture.rows;
    const int w = static_cast<int>(kPictureHeight * aspect);
    place(canvas, picture, {x, 70, w, kPictureHeight}, topic);
    x += w + 20;
  }
  for (const auto& [topic, picture] : pictures) {
    if (topic.rfind("/cameras/", 0) != 0 || topic.find("/image") == std::string::npos || x > 1000) continue;
    const int w = kPictureHeight * picture.cols / std::max(1, picture.rows);
    place(canvas, picture, {x, 70, w, kPictureHeight}, topic);
    x += w + 20;
    break;  // one camera is enough to show they are there
  }
  if (middle_cloud.point_stride() > 0 && x + kPictureHeight <= canvas.cols) {
    place(canvas, cloud_from_above(middle_cloud, kPictureHeight), {x, 70, kPictureHeight, kPictureHeight},
          "/cloud (from above, 10 m)");
  }
  // The timeline: a row per topic, a tick per message.
  const int left = 330, right = canvas.cols - 110, top = 70 + kPictureHeight + 50;
  const int row = std::min(24, (canvas.rows - top - 20) / std::max<int>(1, times.size()));
  int r = 0;
  for (const auto& [topic, ts] : times) {
    const int y = top + r++ * row;
    label(canvas, topic, {20, y + row / 2 + 4}, 0.45, kDim);
    cv::line(canvas, {left, y + row / 2}, {right, y + row / 2}, cv::Scalar(60, 60, 60));
    for (const uint64_t t : ts) {
      const int u = left + static_cast<int>(double(t - t0) / std::max<uint64_t>(1, t1 - t0) * (right - left));
      cv::line(canvas, {u, y + 4}, {u, y + row - 4}, kAccent);
    }
    label(canvas, std::to_string(ts.size()), {right + 10, y + row / 2 + 4}, 0.45, kDim);
  }
  const int mid_u = left + (right - left) / 2;
  cv::line(canvas, {mid_u, top - 6}, {mid_u, top + r * row}, cv::Scalar(0, 200, 255), 2);
  const std::vector<uint8_t> jpeg = encode_jpeg(canvas, 90);
  FILE* f = std::fopen(out_path.c_str(), "wb");
  if (!f || std::fwrite(jpeg.data(), 1, jpeg.size(), f) != jpeg.size()) throw std::runtime_error("cannot write " + out_path);
  std::fclose(f);
  return 0;
}

}  // namespace
}  // namespace omniview

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: mcap-picture FILE.mcap OUT.jpg\n";
    return 2;
  }
  try {
    return omniview::run(argv[1], argv[2]);
  } catch (const std::exception& e) {
    std::cerr << "mcap-picture: " << e.what() << "\n";
    return 1;
  }
}
