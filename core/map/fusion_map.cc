#include "core/map/fusion_map.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/gain/overlap_samples.h"
#include "core/map/adaptive/bands.h"
#include "core/map/footprint.h"
#include "core/map/map_kernels.h"
#include "core/map/parallel_rows.h"
#include "core/map/usable_region.h"

namespace omniview {
namespace {

using namespace map_internal;


CameraSetup make_setup(const Rig& rig, size_t index, const Pose& T_frame_view,
                       const std::string& frame, bool blend, double feather_px, const FeatherSet* feathers) {
  const Camera& cam = rig.cameras()[index];
  CameraSetup s;
  s.camera = &cam;
  const Pose T_cam_view = rig.camera_pose(frame, index).inverse() * T_frame_view;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) s.R[3 * r + c] = static_cast<float>(T_cam_view.linear()(r, c));
    s.t[r] = static_cast<float>(T_cam_view.translation()(r));
  }
  s.limit_fov = cam.fov_deg > 0 && cam.fov_deg < 360;
  s.cos_half_fov = s.limit_fov ? static_cast<float>(std::cos(cam.fov_deg * M_PI / 360)) : -1.0f;
  s.cos2_half_fov = s.cos_half_fov * s.cos_half_fov;
  s.wide_fov = s.cos_half_fov < 0;
  s.max_u = static_cast<float>(cam.width - 1);
  s.max_v = static_cast<float>(cam.height - 1);
  s.limits = SampleLimits{s.max_u, s.max_v, static_cast<float>(cam.width - 2), static_cast<float>(cam.height - 2),
                          cam.width};
  s.centre = CentreScore::of(cam);
  if (blend) {
    s.feather = feathers ? feathers->weights[index] : feather_weights(cam, feather_px);
    const Eigen::Vector3d c = T_cam_view.inverse().translation();
    for (int r = 0; r < 3; ++r) s.centre_view[r] = static_cast<float>(c(r));
    // sqrt(score) * width is (about) the distance from the image centre in pixels: a pixel
    // feather_px / 2 further out than the other camera's loses a factor e in weight, so in
    // a wide overlap the blend band is about feather_px wide around the line where both
    // cameras are equally far off centre (the paper's nearest-centre seam, where their
    // distortion and vignetting agree best), rather than a 50/50 mix across all of it.
    s.centre_falloff = static_cast<float>(2.0 * cam.width / feather_px);
  }
  return s;
}

}  // namespace

double FusionMap::coverage() const {
  if (primary.empty()) return 0;
  const auto seen = std::count_if(primary.begin(), primary.end(), [](const MapEntry& e) { return e.cam != kNoCamera; });
  return static_cast<double>(seen) / static_cast<double>(primary.size());
}

FusionMap build_map(const Rig& rig, const View& view, MapPrecision precision, Sampling sampling,
                    const Occlusion* occlusion, const FeatherSet* feathers) {
  const auto& cameras = rig.cameras();
  if (cameras.size() >= kNoCamera) {
    throw std::invalid_argument("a rig may have at most 254 cameras, this one has " + std::to_string(cameras.size()));
  }
  const ViewSpec& spec = view.spec();
  const std::string frame = spec.frame.empty() ? rig.default_frame() : spec.frame;
  if (!rig.frames().has_frame(frame)) {
    throw std::invalid_argument("view '" + spec.name + "': frame '" + frame + "' is not in the rig");
  }
  const bool blend = spec.fusion == Fusion::kBlend;
  if (occlusion && occlusion->cameras.size() != cameras.size()) {
    throw std::invalid_argument("view '" + spec.name + "': occlusion for " + std::to_string(occlusion->cameras.size()) +
                                " cameras, the rig has " + std::to_string(cameras.size()));
  }
  if (occlusion && !occlusion->judged.empty() &&
      occlusion->judged.size() != size_t(view.width()) * size_t(view.height())) {
    throw std::invalid_argument("view '" + spec.name + "': occlusion's pixel mask is not the view's size");
  }
  const Pose T_frame_view = spec.T_frame_view();
  if (feathers && !feathers->fits(rig, spec.feather_px)) feathers = nullptr;
  std::vector<CameraSetup> setups;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (!rig.frames().try_lookup(frame, cameras[i].name)) {
      throw std::invalid_argument("view '" + spec.name + "': frame '" + frame + "' is not connected to camera '" +
                                  cameras[i].name + "'");
    }
    setups.push_back(make_setup(rig, i, T_frame_view, frame, blend, spec.feather_px, feathers));
  }

  FusionMap map;
  map.width = view.width();
  map.height = view.height();
  map.fusion = spec.fusion;
  const size_t n = static_cast<size_t>(map.width) * static_cast<size_t>(map.height);
  const bool exact = precision == MapPrecision::kExact || map.width < 2 || map.height < 2;
  if (cameras.empty()) {
    // A rig whose cameras are not known yet (a robot that has not answered): all black.
    map.primary.assign(n, kBlackEntry);
    if (blend) {
      map.secondary.assign(n, kBlackEntry);
      map.primary_weight.assign(n, 256);
    }
    return map;
  }
  if (exact) {
    map.primary.assign(n, kBlackEntry);  // the exact builders keep the best candidate so far
  } else {
    map.primary.resize(n);  // the adaptive builder writes every entry, in its own thread
  }
  if (blend) {
    map.secondary.assign(n, kBlackEntry);
    map.primary_weight.assign(n, 256);
  }
  for (const auto& c : cameras) {
    map.camera_sizes.emplace_back(c.width, c.height);
    map.camera_names.push_back(c.name);
  }

  // Which cameras the map reads, gathered by each worker from the rows it just wrote.
  std::vector<std::atomic<bool>> used(cameras.size());
  const auto mark_used = [&](int row_begin, int row_end) {
    std::vector<uint8_t> local(cameras.size(), 0);
    for (const MapEntries* entries : {&map.primary, &map.secondary}) {
      if (entries->empty()) continue;
      const MapEntry* e = entries->data() + static_cast<size_t>(row_begin) * map.width;
      for (size_t i = 0, n = static_cast<size_t>(row_end - row_begin) * map.width; i < n; ++i) {
        if (e[i].cam != kNoCamera) local[e[i].cam] = 1;
      }
    }
    for (size_t c = 0; c < local.size(); ++c) {
      if (local[c]) used[c].store(true, std::memory_order_relaxed);
    }
  };
  if (exact) {
    parallel_rows(cv::Range(0, map.height), [&](const cv::Range& rows) {
      build_rows_exact(view, setups, blend, map, rows.start, rows.end, occlusion);
      mark_used(rows.start, rows.end);
    });
  } else {
    // Runs of kBandsPerTask bands: a run shares lattice rows between its bands, and 16
    // tasks for a 512-row view keep both threads busy to the end (OpenCV hands out tasks
    // one by one; the fisheye view's middle rows cost more than its black corners).
    constexpr int kBandsPerTask = 4;
    const int bands = adaptive_band_count(map.height);
    const int tasks = (bands + kBandsPerTask - 1) / kBandsPerTask;
    parallel_rows(cv::Range(0, tasks), [&](const cv::Range& range) {
      std::vector<uint8_t> local(cameras.size(), 0);
      const int end = std::min(bands, range.end * kBandsPerTask);
      build_bands_adaptive(view, setups, map, range.start * kBandsPerTask, end, local, occlusion, blend);
      for (size_t c = 0; c < local.size(); ++c) {
        if (local[c]) used[c].store(true, std::memory_order_relaxed);
      }
    });
  }
  map.camera_used.resize(cameras.size());
  for (size_t c = 0; c < cameras.size(); ++c) map.camera_used[c] = used[c].load();
  if (sampling == Sampling::kFootprint) assign_footprint_levels(map);
  if (blend && spec.gain_compensation) map.gain_samples = choose_overlap_samples(map);
  return map;
}

}  // namespace omniview
