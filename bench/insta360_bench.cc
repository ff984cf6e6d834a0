// Insta360 Air capture path, with its anchors measured in the same run:
//   - decode + split of a full 3008x1504 Air frame (TurboJPEG straight into packed BGR;
//     the split is the lens layout's shared frame) vs cv::imdecode of the same JPEG;
//   - the same at 1/2 size by DCT scaling vs cv::imdecode + cv::resize (INTER_AREA);
//   - capture -> panorama: the `insta360` source fed by a fake Air at 30 fps, each frame
//     decoded (DCT scale from the view's sampling) and mapped into a 1024x512 equirect;
//     reports the CPU it takes as a percentage of one core.
// The frame is the bundled sample recording's (config/insta360/sample).
#include <benchmark/benchmark.h>

#include <sys/resource.h>

#include <fstream>
#include <iterator>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/view/view.h"
#include "core/view/view_yaml.h"
#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/source/capture_config.h"
#include "server/pipeline/camera_sampling.h"
#include "tests/insta360/fake_air.h"

using namespace omniview;
using namespace omniview::insta360;

namespace {

const std::vector<uint8_t>& air_frame() {
  static const std::vector<uint8_t> bytes = [] {
    std::ifstream in(std::string(OMNIVIEW_SOURCE_DIR) + "/config/insta360/sample/frame_0000.jpg", std::ios::binary);
    return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }();
  return bytes;
}

// What the source hands the pipeline: both lens cameras share the decoded frame.
std::vector<cv::Mat> split(const cv::Mat& frame) { return {frame, frame}; }

void BM_TurboJpegDecodeSplit(benchmark::State& state) {
  const auto& jpeg = air_frame();
  JpegDecoder decoder;
  const int scale = int(state.range(0));
  for (auto _ : state) {
    auto images = split(decoder.decode(jpeg.data(), jpeg.size(), scale));
    benchmark::DoNotOptimize(images[0].data);
  }
  state.SetLabel("1/" + std::to_string(scale));
}
BENCHMARK(BM_TurboJpegDecodeSplit)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ImdecodeAnchor(benchmark::State& state) {
  const auto& jpeg = air_frame();
  const cv::Mat buffer(1, int(jpeg.size()), CV_8UC1, const_cast<uint8_t*>(jpeg.data()));
  for (auto _ : state) {
    cv::Mat image = cv::imdecode(buffer, cv::IMREAD_COLOR);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_ImdecodeAnchor)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ImdecodeResizeAnchor(benchmark::State& state) {
  const auto& jpeg = air_frame();
  const cv::Mat buffer(1, int(jpeg.size()), CV_8UC1, const_cast<uint8_t*>(jpeg.data()));
  for (auto _ : state) {
    cv::Mat image = cv::imdecode(buffer, cv::IMREAD_COLOR), half;
    cv::resize(image, half, {image.cols / 2, image.rows / 2}, 0, 0, cv::INTER_AREA);
    benchmark::DoNotOptimize(half.data);
  }
}
BENCHMARK(BM_ImdecodeResizeAnchor)->Unit(benchmark::kMillisecond)->UseRealTime();

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

// The capture thread decodes (at the scale the view allows) and a render step maps each
// frame into the panorama, as the daemon's render thread does.
void BM_CaptureToPanorama30fps(benchmark::State& state) {
  auto air = std::make_shared<testing::FakeAirState>();
  air->jpeg = air_frame();
  air->fps = 30;
  const auto reader = YamlReader::from_string("name: air\ntype: insta360\nmount: [0, 0, 1, 0, 0, 0]\n", "bench");
  SourceConfig config{"air", &reader, reader.root(), "sources[0]", ""};
  CaptureSource source("air", read_capture_settings(config, "insta360", testing::fake_air_opener(air)));
  const auto view_reader = YamlReader::from_string(
      "name: panorama\ntype: equirectangular\nwidth: 1024\nheight: 512\nframe: insta360\nradius: 3\n"
      "fusion: blend\n", "bench view");
  const ViewSpec spec = parse_view(view_reader, view_reader.root(), "view");
  const auto view = View::create(spec);
  std::mutex mutex;
  std::shared_ptr<const Rig> map_rig;
  FusionMap map;
  uint64_t rendered = 0;
  {
    const FusionMap full = build_map(*source.rig(), *view);
    source.set_camera_sampling(camera_sampling(full));
  }
  cv::setNumThreads(1);  // one render thread, as OMNIVIEW_THREADS=1: the figure is per core
  source.start([&](std::shared_ptr<const FrameSet> frames) {
    std::lock_guard lock(mutex);
    if (frames->rig != map_rig) {  // the scaled rig arrives with the first frame: map once
      map = build_map(*frames->rig, *view);
      map_rig = frames->rig;
      return;
    }
    cv::Mat out;
    apply_map(map, frames->images, out, 3);
    ++rendered;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // opened, first map built
  for (auto _ : state) {
    uint64_t start_frames;
    {
      std::lock_guard lock(mutex);
      start_frames = rendered;
    }
    const double cpu0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::seconds(3));
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - cpu0;
    std::lock_guard lock(mutex);
    state.counters["fps"] = double(rendered - start_frames) / wall;
    state.counters["cpu_pct_of_one_core"] = 100 * cpu / wall;
    state.counters["decode_scale"] = source.counters().decode_scale;
  }
  source.stop();
}
BENCHMARK(BM_CaptureToPanorama30fps)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
