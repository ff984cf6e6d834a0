// Gain compensation and seam placement on the synthetic scene: cameras rendered with
// different exposures, fused by a blend view, with and without per-camera gains.
//
// Seam step: the mean absolute difference of the two cameras' samples over the overlap.
// PSNR: against the scene's truth times the global gain that fits best. Measured (the
// tests print every figure):
//   two colour cameras at 0.7 / 1.3, 1024x512: step 72.6 -> 1.9 grey levels (38x),
//     PSNR 16.1 -> 37.2 dB
//   Spot's front view (config/spot.yaml), five grey cameras at 0.7 / 1.3 / 1.0 / 1.15 / 0.85:
//     step 51.4 -> 1.0 (50x), PSNR 16.6 -> 41.2 dB
//   equal exposures: gains within 0.001 of 1, PSNR unchanged (52.75 and 52.79 dB both ways)
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/gain/gain_compensator.h"
#include "core/map/apply.h"
#include "core/map/usable_region.h"
#include "core/synthetic/render.h"
#include "core/view/view.h"
#include "tests/golden/golden.h"

namespace omniview {
namespace {

struct Case {
  std::string name;
  Rig rig;
  ViewSpec spec;
  std::string world;
  std::vector<double> exposures;  // per camera: rendered image times this
  bool grey = false;
};

struct Measured {
  double step = 0;  // mean |camera a - camera b| over the overlap, grey levels
  double psnr_db = 0;  // against the truth times the best global gain
  double global_gain = 0;
};

// Per output pixel where the map blends two cameras: each camera on its own (with the
// gains), compared. The mean absolute difference is the intensity step a seam shows.
double seam_step(const FusionMap& map, const std::vector<cv::Mat>& images, int oc, CameraGains gains) {
  if (gains.empty()) {  // gains of 1: the same rows (and rounding) as with compensation
    gains.channels = oc;
    gains.gain.assign(map.camera_sizes.size() * oc, 1.0f);
  }
  FusionMap a = map;
  a.secondary.clear();
  a.primary_weight.clear();
  a.gain_samples.clear();
  FusionMap b = a;
  b.primary = map.secondary;
  cv::Mat A, B;
  apply_map(a, images, A, oc, gains);
  apply_map(b, images, B, oc, gains);
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < map.primary.size(); ++i) {
    if (map.primary[i].cam == kNoCamera || map.secondary[i].cam == kNoCamera) continue;
    for (int c = 0; c < oc; ++c) {
      sum += std::abs(int(A.data[i * oc + c]) - int(B.data[i * oc + c]));
      ++n;
    }
  }
  EXPECT_GT(n, 1000u) << "the view must have an overlap to measure";
  return n ? sum / double(n) : 0;
}

// PSNR of `out` against the scene's truth (the texture at the surface points) scaled by the
// global gain that fits best: compensation may settle anywhere between the exposures.
void score(const cv::Mat& out, const cv::Mat& truth, const cv::Mat& covered, Measured& m) {
  double or_ = 0, rr = 0;
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols * out.channels(); ++u) {
      if (!covered.at<uint8_t>(v, u / out.channels())) continue;
      const double o = out.ptr<uint8_t>(v)[u], r = truth.ptr<uint8_t>(v)[u];
      or_ += o * r, rr += r * r;
    }
  }
  m.global_gain = or_ / rr;
  double se = 0;
  size_t n = 0;
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols * out.channels(); ++u) {
      if (!covered.at<uint8_t>(v, u / out.channels())) continue;
      const double d = out.ptr<uint8_t>(v)[u] - std::min(255.0, m.global_gain * truth.ptr<uint8_t>(v)[u]);
      se += d * d, ++n;
    }
  }
  m.psnr_db = 10 * std::log10(255.0 * 255.0 / std::max(se / double(n), 1e-12));
}

struct Outcome {
  Measured plain, compensated;
  CameraGains gains;
};

Outcome run(const Case& c) {
  const int oc = c.grey ? 1 : 3;
  std::vector<cv::Mat> images;
  const auto scene = golden::matching_scene(c.rig, c.spec, c.world);
  for (size_t i = 0; i < c.rig.cameras().size(); ++i) {
    const cv::Mat img = synthetic::render_camera(scene, c.rig, i, c.world, {.supersample = 2, .grey = c.grey});
    cv::Mat exposed;
    img.convertTo(exposed, -1, c.exposures[i]);  // saturates, as a sensor does
    images.push_back(exposed);
  }
  const auto view = View::create(c.spec);
  const FusionMap map = build_map(c.rig, *view);
  EXPECT_FALSE(map.gain_samples.empty());

  const std::string frame = c.spec.frame.empty() ? c.rig.default_frame() : c.spec.frame;
  cv::Mat on_surface, truth = synthetic::texture_at_view(*view, c.rig.frames().lookup(c.world, frame) * c.spec.T_frame_view(),
                                                         &on_surface);
  if (c.grey) cv::cvtColor(truth, truth, cv::COLOR_BGR2GRAY);
  cv::Mat covered = on_surface.clone();
  for (size_t i = 0; i < map.primary.size(); ++i) {
    if (map.primary[i].cam == kNoCamera) covered.data[i] = 0;
  }

  Outcome o;
  GainCompensator compensator;
  o.gains = compensator.update(map, images, oc);
  for (auto [gains, m] : {std::pair{CameraGains{}, &o.plain}, std::pair{o.gains, &o.compensated}}) {
    cv::Mat out;
    apply_map(map, images, out, oc, gains);
    m->step = seam_step(map, images, oc, gains);
    score(out, truth, covered, *m);
  }
  std::cout << "[ gain ] " << c.name << ": seam step " << o.plain.step << " -> " << o.compensated.step
            << " grey levels, PSNR " << o.plain.psnr_db << " -> " << o.compensated.psnr_db << " dB; gains";
  for (size_t i = 0; i < o.gains.cameras(); ++i) std::cout << " " << o.gains.at(i, 0);
  std::cout << "\n";
  return o;
}

Case two_cameras(std::vector<double> exposures) {
  Rig rig("base");
  const CameraModel model(PinholeRadtan(330, 330, 319.5, 239.5));
  rig.add_camera(golden::camera("left", model, 640, 480, Vec3(0, 0.05, 0), 30, 0, 0));
  rig.add_camera(golden::camera("right", model, 640, 480, Vec3(0, -0.05, 0), -30, 0, 0));
  ViewSpec v = default_view_spec(ViewType::kPerspective);
  v.name = "front";
  v.width = 1024, v.height = 512;
  v.hfov_deg = 110;
  v.distance = 3;
  return {"two colour cameras", rig, v, "base", std::move(exposures), false};
}

// config/spot.yaml's front view.
Case spot_front(std::vector<double> exposures) {
  ViewSpec v = default_view_spec(ViewType::kPerspective);
  v.name = "front";
  v.width = 1024, v.height = 512;
  v.frame = "body";
  v.position = Vec3(0.42, 0, 0);
  v.pitch_deg = 25;
  v.hfov_deg = 120;
  v.distance = 3;
  v.feather_px = 30;
  return {"spot front", golden::spot_like_rig(), v, "body", std::move(exposures), true};
}

TEST(GainCompensation, TwoCamerasWithDifferentExposuresMeetWithoutAStep) {
  const auto o = run(two_cameras({0.7, 1.3}));
  EXPECT_LT(o.compensated.step, o.plain.step / 10);
  EXPECT_GT(o.compensated.psnr_db, o.plain.psnr_db + 10);
  // The gains undo the exposures up to one common factor, in every channel.
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(o.gains.at(0, c) * 0.7 / (o.gains.at(1, c) * 1.3), 1.0, 0.03);
}

TEST(GainCompensation, SpotFrontViewWithFiveExposures) {
  const auto o = run(spot_front({0.7, 1.3, 1.0, 1.15, 0.85}));
  EXPECT_LT(o.compensated.step, o.plain.step / 5);
  EXPECT_GT(o.compensated.psnr_db, o.plain.psnr_db + 6);
  // The front pair, up to the pull of the prior and of the side cameras' overlaps.
  EXPECT_NEAR(o.gains.at(0, 0) * 0.7 / (o.gains.at(1, 0) * 1.3), 1.0, 0.05);
}

TEST(GainCompensation, EqualExposuresLoseNothing) {
  for (const auto& c : {two_cameras({1, 1}), spot_front({1, 1, 1, 1, 1})}) {
    const auto o = run(c);
    EXPECT_GE(o.compensated.psnr_db, o.plain.psnr_db - 0.1) << c.name;
    for (float g : o.gains.gain) EXPECT_NEAR(g, 1.0, 0.02) << c.name;
  }
}

}  // namespace
}  // namespace omniview
