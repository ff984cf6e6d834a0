#include "cli/colorize_command.h"

#include <filesystem>
#include <iostream>
#include <memory>

#include <opencv2/core/utils/logger.hpp>

#include "cli/args.h"
#include "cli/rig_args.h"
#include "core/cloud/cloud_file.h"
#include "core/cloud/colourer.h"

namespace omniview::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kColorizeHelp = R"(usage: omniview colorize --rig RIG.yaml --image CAM=PATH ... --cloud IN.ply|IN.pcd -o OUT.ply
                         [--cloud-frame FRAME] [--fusion nearest|blend] [--no-occlusion] [--ascii]

Colours a point cloud from a calibrated rig and one image per camera: each point takes the
colour of the camera that sees it nearest its image centre (or a feathered blend), unless a
nearer surface of the cloud hides it in that camera. The robot is assumed still between the
cloud and the images (all are taken as simultaneous). Points no camera colours keep the
colour their input file gave them, else r, g, b 0; the output's 'flags' (1 coloured,
2 occluded, 4 self) and 'camera' fields say what happened to each point. A camera given no
--image colours nothing (said on stderr).

)";

constexpr const char* kOwnHelp = R"(  --cloud FILE        the cloud: PLY or PCD, ASCII or binary
  --cloud-frame NAME  the rig frame the cloud's points are in (default: the frame the file
                      names, else the rig's frame)
  --fusion MODE       nearest (default: the camera whose pixel is nearest its centre) or blend
  --no-occlusion      colour points even where a nearer surface hides them (the reference method)
  -o, --out FILE      the coloured cloud: .ply (binary; MeshLab and CloudCompare open it) or .pcd
  --ascii             write ASCII instead of binary
  -h, --help          this help
)";

const OptionSpec kColorizeOptions{.switches = {"no-occlusion", "ascii"},
                          .single = {"rig", "rig-frame", "rig-pose", "cloud", "cloud-frame", "fusion", "out"},
                          .repeatable = {"image"}};

}  // namespace

int colorize_command(const std::vector<std::string>& argv_in) {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  std::vector<std::string> argv = argv_in;
  for (auto& a : argv) {
    if (a == "-o") a = "--out";
  }
  const Args args = Args::parse(argv, kColorizeOptions);
  if (args.help_requested()) {
    std::cout << kColorizeHelp << kRigOptionsHelp << kOwnHelp;
    return 0;
  }
  if (!args.positional().empty()) throw UsageError("unexpected argument '" + args.positional()[0] + "'");
  for (const char* needed : {"rig", "image", "cloud", "out"}) args.required(needed);
  const std::string out = args.get("out");
  {
    std::string ext = fs::path(out).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".ply" && ext != ".pcd") throw UsageError("--out " + out + ": give a .ply or .pcd file name");
  }
  ColourOptions options;
  const std::string fusion = args.get("fusion", "nearest");
  if (fusion == "nearest") {
    options.fusion = Fusion::kNearestCentre;
  } else if (fusion == "blend") {
    options.fusion = Fusion::kBlend;
  } else {
    throw UsageError("--fusion must be 'nearest' or 'blend', not '" + fusion + "'");
  }
  options.occlusion = !args.has("no-occlusion");

  auto loaded = std::make_shared<LoadedRig>(load_rig_from_args(args));
  const std::shared_ptr<const Rig> rig(loaded, &loaded->rig);
  CameraImages images{read_images(args, *rig), {}};
  // Allowed (a rig may have cameras the scan's moment has no picture of), but said: points
  // only those cameras see come out unseen, which looks like a colouring fault otherwise.
  std::vector<std::string> without;
  for (size_t c = 0; c < images.images.size(); ++c) {
    if (images.images[c].empty()) without.push_back(rig->cameras()[c].name);
  }
  if (!without.empty()) {
    std::cerr << "omniview colorize: no image for camera" << (without.size() > 1 ? "s " : " ") << joined(without)
              << ": the points only " << (without.size() > 1 ? "they see" : "it sees")
              << " stay uncoloured (add --image CAM=PATH)\n";
  }
  PointCloud cloud = load_cloud(args.get("cloud"));
  if (args.has("cloud-frame")) cloud.frame = args.get("cloud-frame");
  if (!cloud.frame.empty() && !rig->frames().try_lookup(rig->default_frame(), cloud.frame)) {
    throw UsageError("the cloud's frame '" + cloud.frame + "'" + (args.has("cloud-frame") ? "" : " (named in the file)") +
                     " is not a frame of the rig (known frames: " + joined(rig->known_frames()) +
                     "); give --cloud-frame");
  }
  // The file's own "unseen" colour: keep what it had, else none (0 with flags saying so).
  CloudColourer colourer(rig);
  const ColourStats stats = colourer.colour(cloud, images, options);
  save_cloud(cloud, out, args.has("ascii") ? CloudEncoding::kAscii : CloudEncoding::kBinary);
  std::cout << out << ": " << stats.points << " points: " << stats.coloured << " coloured, " << stats.occluded
            << " occluded, " << stats.self_filtered << " self-filtered, " << stats.unseen << " unseen\n";
  return 0;
}

}  // namespace omniview::cli
