// Renders the bundled Insta360 Air sample recording (config/insta360/sample): what an Air
// mounted as config/insta360.yaml says would stream of a synthetic scene, through the
// built-in nominal calibration, as the Air's 3008 x 1504 dual-fisheye MJPEG frames.
//
// The scene is the furnished room spot-mock shows (synthetic::Scene::room(): walls, tiled
// floor, two columns, two cabinets), the Air 1 m above the floor as the config mounts it,
// so the sample's panorama looks like a place. The daemon's panorama of this recording
// must match the room ray-cast from the panorama's own centre (the done-when test,
// tests/insta360/air_daemon_test.cc, checks it by PSNR).
//
//   omniview_make_air_sample [--config config/insta360.yaml] [--out DIR] [--frames N] [--quality Q]
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>

#include "core/io/image_codec.h"
#include "core/synthetic/render.h"
#include "insta360_adapter/source/capture_config.h"
#include "server/config/daemon_config.h"

using namespace omniview;

int main(int argc, char** argv) {
  std::string config_file = std::string(OMNIVIEW_SOURCE_DIR) + "/config/insta360.yaml";
  std::string out = std::string(OMNIVIEW_SOURCE_DIR) + "/config/insta360/sample";
  int frames = 3, quality = 70, supersample = 2;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--config") config_file = v;
    else if (a == "--out") out = v;
    else if (a == "--frames") frames = std::stoi(v);
    else if (a == "--quality") quality = std::stoi(v);
    else if (a == "--supersample") supersample = std::stoi(v);
    else {
      std::cerr << "usage: omniview_make_air_sample [--config F] [--out DIR] [--frames N] [--quality Q] [--supersample S]\n";
      return 2;
    }
  }
  try {
    const DaemonConfig config = load_daemon_config(config_file);
    const SourceEntry& entry = config.sources.at(0);
    SourceConfig sc{entry.name, config.reader.get(), entry.node, entry.path, config.folder};
    // The recording does not exist yet: nothing is opened.
    const auto settings = insta360::read_capture_settings(sc, "insta360", [] { return nullptr; });
    const Rig& rig = *settings.calibration;
    // The room's floor is z = 0 of the rig's own frame (base_link), where the mount puts
    // the camera 1 m up.
    const std::string world = rig.default_frame();
    const auto scene = synthetic::Scene::room();
    cv::Mat frame = cv::Mat::zeros(settings.frame_size, CV_8UC3);
    for (const auto& crop : settings.crops) {
      size_t index = 0;
      while (rig.cameras()[index].name != crop.camera) ++index;
      synthetic::RenderOptions options;
      options.supersample = supersample;
      synthetic::render_camera(scene, rig, index, world, options).copyTo(frame(crop.rect));
    }
    std::filesystem::create_directories(out);
    std::ofstream times(std::filesystem::path(out) / "timestamps.txt");
    times << "# capture time (s) and frame: rendered by omniview_make_air_sample from " << "config/insta360.yaml\n";
    // A camera's frame times jitter by a millisecond or so around its 30 Hz.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.0015, 0.0015);
    for (int i = 0; i < frames; ++i) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04d.jpg", i);
      const std::vector<uint8_t> jpeg = encode_jpeg(frame, quality);
      std::ofstream(std::filesystem::path(out) / name, std::ios::binary).write(reinterpret_cast<const char*>(jpeg.data()), std::streamsize(jpeg.size()));
      char line[64];
      std::snprintf(line, sizeof line, "%.4f %s\n", 100.0 + i / 30.0 + (i ? jitter(rng) : 0), name);
      times << line;
      std::cout << name << ": " << jpeg.size() / 1024 << " KiB\n";
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "omniview_make_air_sample: " << e.what() << "\n";
    return 1;
  }
}
