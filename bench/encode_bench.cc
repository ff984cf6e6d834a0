// Encoding a view frame: ours beside the anchor, OpenCV's cv::imencode, in the same run.
// JPEG: TurboJPEG from the view buffer (server/pipeline/frame_encoder.cc); PNG: libpng at
// zlib level 1, SUB filter, run-length matching (core/io/png_codec.cc) against OpenCV at
// the compression 1 streams used before. Single-threaded: one encode per (view, encoding)
// runs on one encoder thread.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "server/pipeline/frame_encoder.h"

namespace omniview {
namespace {

// A rendered view with natural-ish content: the example rig's front image, resized.
cv::Mat view_frame(int w, int h, bool colour) {
  cv::Mat img = cv::imread(OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye/front.jpg", cv::IMREAD_COLOR);
  if (img.empty()) {  // no example image: smooth gradients and noise
    img.create(h, w, CV_8UC3);
    cv::randu(img, 0, 255);
    cv::GaussianBlur(img, img, {0, 0}, 3);
  }
  cv::resize(img, img, {w, h}, 0, 0, cv::INTER_AREA);
  if (!colour) cv::cvtColor(img, img, cv::COLOR_BGR2GRAY);
  return img;
}

void BM_EncodeJpeg(benchmark::State& state, int w, int h, bool colour) {
  const cv::Mat img = view_frame(w, h, colour);
  const EncodingKey key = encoding_key(v1::JPEG, 85, false);
  for (auto _ : state) {
    v1::Frame frame;
    encode_frame(img, key, frame);
    benchmark::DoNotOptimize(frame.data().size());
  }
}

void BM_CvImencode(benchmark::State& state, int w, int h, bool colour) {
  const cv::Mat img = view_frame(w, h, colour);
  std::vector<uint8_t> bytes;
  for (auto _ : state) {
    cv::imencode(".jpg", img, bytes, {cv::IMWRITE_JPEG_QUALITY, 85});
    benchmark::DoNotOptimize(bytes.data());
  }
}

// The PNG client of a big view (bench/daemon_load.cc's BM_JpegBesidePng): 2048x1024 colour.
void BM_EncodePng(benchmark::State& state, int w, int h, bool colour) {
  const cv::Mat img = view_frame(w, h, colour);
  const EncodingKey key = encoding_key(v1::PNG, 0, false);
  size_t bytes = 0;
  for (auto _ : state) {
    v1::Frame frame;
    encode_frame(img, key, frame);
    bytes = frame.data().size();
  }
  state.counters["KiB"] = static_cast<double>(bytes) / 1024;
}

void BM_CvImencodePng(benchmark::State& state, int w, int h, bool colour) {
  const cv::Mat img = view_frame(w, h, colour);
  std::vector<uint8_t> bytes;
  for (auto _ : state) cv::imencode(".png", img, bytes, {cv::IMWRITE_PNG_COMPRESSION, 1});
  state.counters["KiB"] = static_cast<double>(bytes.size()) / 1024;
}

BENCHMARK_CAPTURE(BM_EncodeJpeg, 1024x512_rgb, 1024, 512, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CvImencode, 1024x512_rgb, 1024, 512, true)->Name("BM_Anchor_cv_imencode_jpeg_1024x512_rgb")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EncodeJpeg, 1024x512_grey, 1024, 512, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CvImencode, 1024x512_grey, 1024, 512, false)->Name("BM_Anchor_cv_imencode_jpeg_1024x512_grey")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_EncodePng, 2048x1024_rgb, 2048, 1024, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_CvImencodePng, 2048x1024_rgb, 2048, 1024, true)->Name("BM_Anchor_cv_imencode_png_2048x1024_rgb")->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
