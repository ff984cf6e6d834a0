// `omniview render --cloud FILE [--cloud-frame NAME]`: the measured points that views with
// `depth: measured` stand on (core/depth), read and checked before any view is rendered.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cli/args.h"
#include "cli/rig_args.h"
#include "core/depth/column_completion.h"
#include "core/rig/rig.h"

namespace omniview::cli {

// More points than a few minutes of a 32-laser lidar is a wrong file, not a room: refused
// before it takes the machine's memory (also a file larger than kMaxCloudFileBytes).
inline constexpr size_t kMaxCloudPoints = 20'000'000;
inline constexpr size_t kMaxCloudFileBytes = size_t(2) << 30;  // 2 GiB

struct RenderCloud {
  std::string file;
  std::string frame;                    // the rig frame the file's points are in
  std::vector<Eigen::Vector3f> points;  // in the rig's default (robot) frame
  Completion completion;                // what completes them (core/depth/column_completion.h)
  size_t non_finite = 0;  // points without a return (NaN, inf): kept, the depth code skips them
};

// Reads --cloud (PLY or PCD, by content). Its frame: --cloud-frame, else the frame the file
// records (omniview writes it), else the rig's default frame. Throws std::runtime_error
// naming the file for a malformed, empty or oversized cloud, or a frame the rig lacks.
RenderCloud load_render_cloud(const Args& args, const Rig& rig);

}  // namespace omniview::cli
