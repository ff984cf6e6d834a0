// The rig and camera-image arguments that offline commands share (`omniview render`,
// `omniview colorize`): --rig (our rig YAML or a kalibr camchain, with --rig-frame and
// --rig-pose for camchains) and --image CAM=PATH.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "cli/args.h"
#include "core/rig/rig.h"

namespace omniview::cli {

// Help lines for those options, for commands' --help.
extern const char* const kRigOptionsHelp;

struct LoadedRig {
  Rig rig;
  bool camchain = false;
};

std::string joined(const std::vector<std::string>& words, const std::string& separator = ", ");
// Whitespace- or comma-separated numbers, each one whole and finite; `option` names them in errors.
std::vector<double> parse_numbers(std::string text, const std::string& option);
// "x y z yaw pitch roll" (metres, degrees) or "x y z qx qy qz qw".
Pose parse_rig_pose(const std::string& text);
// --rig with --rig-frame / --rig-pose (camchains only).
LoadedRig load_rig_from_args(const Args& args);
// One image per camera index from --image CAM=PATH; empty where none names the camera.
std::vector<cv::Mat> read_images(const Args& args, const Rig& rig);

}  // namespace omniview::cli
