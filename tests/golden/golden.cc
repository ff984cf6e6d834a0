#include "tests/golden/golden.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/map/apply.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"

namespace omniview::golden {
namespace {

bool is_grey(Inputs inputs, size_t camera) {
  return inputs == Inputs::kGrey || (inputs == Inputs::kMixed && camera % 2 == 0);
}

double psnr(double squared_error, size_t samples) {
  const double mse = samples ? squared_error / double(samples) : 1e9;
  return 10 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
}

}  // namespace

const cv::Mat& Renders::image(size_t camera, bool grey) {
  cv::Mat& colour = colour_.at(camera);
  if (colour.empty()) colour = synthetic::render_camera(scene_, rig_, camera, world_frame_, {.supersample = 3});
  if (!grey) return colour;
  cv::Mat& luma = grey_[camera];
  if (luma.empty()) cv::cvtColor(colour, luma, cv::COLOR_BGR2GRAY);
  return luma;
}

Score run(Renders& renders, const Rig& map_rig, const ViewSpec& spec, Inputs inputs, int out_channels) {
  const Rig& render_rig = renders.rig();
  const std::string& world_frame = renders.world_frame();
  const size_t n = render_rig.cameras().size();
  const auto view = View::create(spec);
  // Bilinear sampling everywhere: the reference is the texture at each pixel's centre, which
  // checks geometry; footprint_test.cc measures footprint-aware sampling against a
  // box-filtered reference instead.
  const FusionMap map = build_map(map_rig, *view, MapPrecision::kAdaptive, Sampling::kBilinear);
  // Only the cameras the map reads are rendered; the others get black images of their size.
  std::vector<cv::Mat> images;
  for (size_t i = 0; i < n; ++i) {
    const bool grey = is_grey(inputs, i);
    if (map.camera_used.at(i)) {
      images.push_back(renders.image(i, grey));
    } else {
      const Camera& cam = render_rig.cameras()[i];
      images.emplace_back(cam.height, cam.width, grey ? CV_8UC1 : CV_8UC3, cv::Scalar::all(0));
    }
  }
  Score s;
  apply_map(map, images, s.rendered, out_channels);

  const std::string frame = spec.frame.empty() ? render_rig.default_frame() : spec.frame;
  const Pose T_world_view = render_rig.frames().lookup(world_frame, frame) * spec.T_frame_view();
  cv::Mat on_surface, luma;
  s.reference = synthetic::texture_at_view(*view, T_world_view, &on_surface);
  cv::cvtColor(s.reference, luma, cv::COLOR_BGR2GRAY);

  std::vector<double> squared_error(n, 0);
  std::vector<size_t> pixels(n, 0);
  size_t surface = 0;
  for (int v = 0; v < map.height; ++v) {
    for (int u = 0; u < map.width; ++u) {
      if (!on_surface.at<uint8_t>(v, u)) continue;
      ++surface;
      const uint8_t cam = map.primary[static_cast<size_t>(v) * map.width + u].cam;
      if (cam == kNoCamera) continue;
      ++pixels[cam];
      // A grey camera, or a grey output, has only luma to give.
      const bool luma_only = out_channels == 1 || is_grey(inputs, cam);
      for (int c = 0; c < out_channels; ++c) {
        const double expected = luma_only ? luma.at<uint8_t>(v, u) : s.reference.at<cv::Vec3b>(v, u)[c];
        const double d = double(s.rendered.ptr<uint8_t>(v)[u * out_channels + c]) - expected;
        squared_error[cam] += d * d;
      }
    }
  }
  double total_error = 0;
  size_t covered = 0;
  for (size_t i = 0; i < n; ++i) {
    s.cameras.push_back({map_rig.cameras()[i].name, pixels[i], psnr(squared_error[i], pixels[i] * out_channels)});
    total_error += squared_error[i];
    covered += pixels[i];
  }
  s.coverage = surface ? double(covered) / surface : 0;
  s.psnr_db = psnr(total_error, covered * out_channels);
  if (out_channels == 1) s.reference = luma;
  return s;
}

synthetic::Scene matching_scene(const Rig& rig, const ViewSpec& view, const std::string& world_frame) {
  const std::string frame = view.frame.empty() ? rig.default_frame() : view.frame;
  return synthetic::Scene::matching(view, rig.frames().lookup(world_frame, frame));
}

void report(const std::string& what, const Score& s) {
  std::cout << "[ golden ] " << what << ": PSNR " << s.psnr_db << " dB, coverage " << 100 * s.coverage << " %";
  for (const auto& c : s.cameras) {
    if (c.pixels) std::cout << "; " << c.name << " " << c.psnr_db << " dB over " << c.pixels << " px";
  }
  std::cout << "\n";
}

ViewSpec view(ViewType type, int width, int height) {
  ViewSpec s;
  s.name = to_string(type);
  s.type = type;
  s.width = width;
  s.height = height;
  return s;
}

Camera camera(const std::string& name, CameraModel model, int width, int height, const Vec3& xyz, double yaw_deg,
              double pitch_deg, double roll_deg, double fov_deg) {
  Camera c;
  c.name = name;
  c.model = std::move(model);
  c.width = width;
  c.height = height;
  c.fov_deg = fov_deg;
  const double d = M_PI / 180;
  c.T_parent_cam = make_pose(xyz, yaw_deg * d, pitch_deg * d, roll_deg * d);
  c.T_parent_cam.linear() = c.T_parent_cam.linear() * R_view_optical();  // mount: x = optical axis
  return c;
}

std::string example_dir() { return OMNIVIEW_SOURCE_DIR "/config/examples/dual_fisheye"; }

Rig example_rig() { return load_rig_yaml(example_dir() + "/rig.yaml"); }

ViewSpec example_panorama(int width, int height) {
  ViewSpec v = view(ViewType::kEquirectangular, width, height);
  v.position = Vec3(0, 0, 1);
  v.radius = 3.0;
  return v;
}

Rig with_camera_pose(const Rig& rig, const std::string& name, const Pose& T_parent_cam) {
  Rig out(rig.default_frame());
  for (Camera c : rig.cameras()) {
    if (c.name == name) c.T_parent_cam = T_parent_cam;
    out.add_camera(c);
  }
  return out;
}

Rig mixed_model_ring() {
  Rig rig;
  RadtanDistortion d;
  d.k1 = -0.28, d.k2 = 0.07, d.p1 = 0.0005, d.p2 = -0.0003;
  rig.add_camera(camera("omni", OmniRadtan(0.9, 240, 240, 319.5, 239.5, d), 640, 480, Vec3(0.1, 0, 1), 0, 0, 0, 190));
  rig.add_camera(camera("ds", DoubleSphere(-0.2, 0.6, 180, 180, 319.5, 239.5), 640, 480, Vec3(0, 0.1, 1), 90, 0, 5, 190));
  rig.add_camera(camera("eucm", Eucm(0.6, 1.1, 180, 180, 319.5, 239.5), 640, 480, Vec3(-0.1, 0, 1), 180, 0, -4, 180));
  rig.add_camera(camera("fov", Fov(250, 250, 319.5, 239.5, 0.9), 640, 480, Vec3(0, -0.1, 1), -90, 0, 0));
  RadtanDistortion r;
  r.k1 = -0.1, r.k2 = 0.01, r.p1 = 0.001, r.k3 = -0.001;
  rig.add_camera(camera("radtan", PinholeRadtan(200, 200, 319.5, 239.5, r), 640, 480, Vec3(0, 0, 1.1), 0, -89, 0));
  return rig;
}

}  // namespace omniview::golden
