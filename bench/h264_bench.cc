// H.264 streams (server/video, libx264) of spot-mock's room as the daemon renders it, beside
// JPEG at the same PSNR, in the same run. The sequences: the shipped front view at 640x480
// grey and the bird's-eye view at 800x800 grey, panning (the view turns 1 deg a frame, 15
// deg/s at 15 fps: an operator's PTZ pan, a robot turning), with camera noise (sigma 2 grey
// levels, fresh each frame, on the cameras' images, before the view is sampled).
//
// Counters: kbit_s at 15 fps, psnr_db (mean luma PSNR of the decoded frames against the
// rendered ones, libavcodec decoding), and the time per iteration is one frame's encode
// (single encoder, 2 slice threads as the daemon runs it; one thread beside it).
#include <benchmark/benchmark.h>
#include <turbojpeg.h>

#include <cmath>
#include <map>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"
#include "server/video/h264_encoder.h"
#include "spot_adapter/mock/world/mock_scene.h"
#include "tests/video/h264_decoder.h"

namespace omniview {
namespace {

constexpr double kFps = 15;
constexpr int kFrames = 30;  // 2 s

struct Sequence {
  std::vector<cv::Mat> frames;  // grey, one per 1/15 s
};

ViewSpec front_view(double yaw_deg) {
  ViewSpec s;
  s.name = "front";
  s.type = ViewType::kPerspective;
  s.width = 640;
  s.height = 480;
  s.frame = spot_mock::kBodyFrame;
  s.position = {0.42, 0, 0};
  s.yaw_deg = yaw_deg;
  s.pitch_deg = 27;
  s.hfov_deg = 115;
  s.distance = 3;
  s.fusion = Fusion::kBlend;
  return s;
}

ViewSpec birdseye_view(double yaw_deg) {
  ViewSpec s;
  s.name = "birdseye";
  s.type = ViewType::kBirdseye;
  s.width = 800;
  s.height = 800;
  s.frame = spot_mock::kWorldFrame;  // the robot stands level over its origin: as footprint
  s.yaw_deg = yaw_deg;
  s.pitch_deg = 90;
  s.height_m = 3;
  s.hfov_deg = 110;
  s.fusion = Fusion::kBlend;
  return s;
}

const Sequence& sequence(const std::string& name) {
  static std::map<std::string, Sequence> cache;
  if (const auto it = cache.find(name); it != cache.end()) return it->second;
  static const synthetic::Scene scene = spot_mock::make_scene(spot_mock::SceneKind::kRoom);
  static const Rig rig = spot_mock::mock_rig();
  static const std::vector<cv::Mat> cameras = [] {
    std::vector<cv::Mat> images;
    for (size_t i = 0; i < rig.cameras().size(); ++i) {
      images.push_back(
          synthetic::render_camera(scene, rig, i, spot_mock::kWorldFrame, {.supersample = 2, .grey = true}));
    }
    return images;
  }();
  Sequence seq;
  cv::RNG rng(18);
  for (int i = 0; i < kFrames; ++i) {
    const ViewSpec spec = name == "front" ? front_view(i) : birdseye_view(i);
    const auto view = View::create(spec);
    const FusionMap map = build_map(rig, *view);
    std::vector<cv::Mat> noisy;
    for (const auto& c : cameras) {
      cv::Mat n(c.size(), CV_16SC1);
      rng.fill(n, cv::RNG::NORMAL, 0, 2);
      cv::Mat sum;
      cv::add(c, n, sum, cv::noArray(), CV_8UC1);
      noisy.push_back(sum);
    }
    cv::Mat out;
    apply_map(map, noisy, out, 1);
    seq.frames.push_back(out);
  }
  return cache.emplace(name, std::move(seq)).first->second;
}

// The frames played forward then back, so a long run has no jump (a scene cut).
const cv::Mat& frame_at(const Sequence& seq, long i) {
  const long period = 2 * kFrames - 2;
  const long k = i % period;
  return seq.frames[k < kFrames ? k : period - k];
}

struct Quality {
  double kbit_s = 0;
  double psnr_db = 0;
};

// One pass over the sequence (forward and back) through a fresh encoder and a decoder.
Quality h264_quality(const Sequence& seq, double crf, int threads, const std::string& preset) {
  video::H264Settings s;
  s.preset = preset;
  s.width = seq.frames[0].cols;
  s.height = seq.frames[0].rows;
  s.fps = kFps;
  s.crf = crf;
  s.threads = threads;
  video::H264Encoder encoder(s);
  testing::H264Decoder decoder;
  size_t bytes = 0;
  double db = 0;
  const int n = 2 * kFrames - 2;
  for (int i = 0; i < n; ++i) {
    const auto au = encoder.encode(frame_at(seq, i), std::lround(i * 1000 / kFps), false);
    bytes += au.data.size();
    db += testing::psnr(testing::H264Decoder::luma(decoder.decode(au.data), s.width, s.height), frame_at(seq, i));
  }
  return {bytes * 8.0 / 1000 / (n / kFps), db / n};
}

Quality jpeg_quality(const Sequence& seq, int quality) {
  tjhandle compress = tjInitCompress();
  tjhandle decompress = tjInitDecompress();
  size_t bytes = 0;
  double db = 0;
  for (const auto& f : seq.frames) {
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    tjCompress2(compress, f.data, f.cols, static_cast<int>(f.step[0]), f.rows, TJPF_GRAY, &jpeg, &size, TJSAMP_GRAY,
                quality, 0);
    cv::Mat back(f.size(), CV_8UC1);
    tjDecompress2(decompress, jpeg, size, back.data, f.cols, 0, f.rows, TJPF_GRAY, 0);
    tjFree(jpeg);
    bytes += size;
    db += testing::psnr(back, f);
  }
  tjDestroy(compress);
  tjDestroy(decompress);
  const double n = seq.frames.size();
  return {bytes * 8.0 / 1000 / (n / kFps), db / n};
}

// The encode time of one frame, the stream's bitrate and quality as counters.
void BM_H264(benchmark::State& state, const std::string& view, double crf, int threads, const std::string& preset) {
  const Sequence& seq = sequence(view);
  const Quality q = h264_quality(seq, crf, threads, preset);
  video::H264Settings s;
  s.preset = preset;
  s.width = seq.frames[0].cols;
  s.height = seq.frames[0].rows;
  s.fps = kFps;
  s.crf = crf;
  s.threads = threads;
  video::H264Encoder encoder(s);
  long i = 0;
  for (auto _ : state) {
    const auto au = encoder.encode(frame_at(seq, i), std::lround(i * 1000 / kFps), false);
    benchmark::DoNotOptimize(au.data.data());
    ++i;
  }
  state.counters["kbit_s"] = q.kbit_s;
  state.counters["psnr_db"] = q.psnr_db;
}

// The anchor: JPEG (TurboJPEG, grey, as the daemon sends it) at the lowest quality whose
// PSNR reaches the H.264 stream's at `crf`; the time is one frame's JPEG encode.
void BM_Anchor_JpegSamePsnr(benchmark::State& state, const std::string& view, double crf) {
  const Sequence& seq = sequence(view);
  const double target = h264_quality(seq, crf, 2, video::H264Settings().preset).psnr_db;
  int quality = 1;
  Quality q;
  for (quality = 50; quality <= 100; ++quality) {
    q = jpeg_quality(seq, quality);
    if (q.psnr_db >= target) break;
  }
  tjhandle compress = tjInitCompress();
  long i = 0;
  for (auto _ : state) {
    const cv::Mat& f = frame_at(seq, i++);
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    tjCompress2(compress, f.data, f.cols, static_cast<int>(f.step[0]), f.rows, TJPF_GRAY, &jpeg, &size, TJSAMP_GRAY,
                quality, 0);
    tjFree(jpeg);
  }
  tjDestroy(compress);
  state.counters["kbit_s"] = q.kbit_s;
  state.counters["psnr_db"] = q.psnr_db;
  state.counters["jpeg_quality"] = quality;
}

// The daemon's settings (superfast, 2 slice threads, CRF 26 = quality 50, the default)
// first; then one thread, other CRFs and presets beside them.
#define OMNIVIEW_H264(view, size, crf, threads, preset)                                                        \
  BENCHMARK_CAPTURE(BM_H264, view##_##size##_grey_crf##crf##_##preset##_threads##threads, #view, crf, threads, \
                    #preset)                                                                                   \
      ->Unit(benchmark::kMillisecond)                                                                          \
      ->UseRealTime()
OMNIVIEW_H264(front, 640x480, 26, 2, superfast);
OMNIVIEW_H264(front, 640x480, 26, 1, superfast);
OMNIVIEW_H264(front, 640x480, 23, 2, superfast);
OMNIVIEW_H264(front, 640x480, 30, 2, superfast);
OMNIVIEW_H264(front, 640x480, 26, 2, veryfast);
OMNIVIEW_H264(front, 640x480, 26, 2, ultrafast);
BENCHMARK_CAPTURE(BM_Anchor_JpegSamePsnr, front_640x480_grey_as_crf26, "front", 26)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
OMNIVIEW_H264(birdseye, 800x800, 26, 2, superfast);
OMNIVIEW_H264(birdseye, 800x800, 26, 1, superfast);
OMNIVIEW_H264(birdseye, 800x800, 23, 2, superfast);
OMNIVIEW_H264(birdseye, 800x800, 30, 2, superfast);
OMNIVIEW_H264(birdseye, 800x800, 26, 2, veryfast);
OMNIVIEW_H264(birdseye, 800x800, 26, 2, ultrafast);
BENCHMARK_CAPTURE(BM_Anchor_JpegSamePsnr, birdseye_800x800_grey_as_crf26, "birdseye", 26)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace omniview

BENCHMARK_MAIN();
