// `omniview cloud [SOURCE] -o OUT.ply`: a source's coloured lidar cloud saved as binary PLY
// (or PCD), one, N (--count) or until Ctrl-C (--follow), with the colouring's counts.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "cli/client/client_commands.h"
#include "cli/client/cloud_decode.h"
#include "cli/client/command_support.h"
#include "cli/client/connection.h"
#include "core/cloud/cloud_file.h"

namespace omniview::cli {
namespace {

const std::string kCloudHelp =
    std::string(R"(usage: omniview cloud [SOURCE] -o OUT.ply [--count N | --follow] [--frame F] [--voxel M]
                      [--crop X0,Y0,Z0,X1,Y1,Z1] [--fusion nearest|blend] [--no-occlusion]
                      [--coloured-only] [--rate HZ] [--wait S]

Saves a source's lidar cloud, coloured by the daemon from the same moment's camera images,
as binary PLY with colours (MeshLab, CloudCompare) or PCD (by the extension). Each point
also keeps `flags` (1 coloured, 2 occluded, 4 on the robot) and `camera` (the camera its
colour came from, 255 none); uncoloured points are black unless --coloured-only drops them.
Prints how many points were coloured, occluded, self-filtered and unseen.

  SOURCE             the daemon's source (default: its first)
  -o, --output FILE  .ply or .pcd; with --count or --follow, FILE_000001.ply, ...
  --count N          save N clouds from a stream
  --follow           save clouds until Ctrl-C
  --frame F          the frame the points are in (default: the robot's frame, e.g. body)
  --voxel M          one point per voxel of M metres (0.01..10)
  --crop X0,Y0,Z0,X1,Y1,Z1  keep the points inside this box (in --frame)
  --fusion F         nearest (the camera whose pixel is nearest its centre) or blend
  --no-occlusion     colour points hidden from a camera too (from what hides them)
  --coloured-only    leave out points no camera coloured
  --rate HZ          at most this many clouds a second (--count, --follow)
  --wait S           how long the daemon waits for a cloud (default 5; one cloud)

)") +
    connection_help();

v1::CloudOptions cloud_options(const Args& args) {
  v1::CloudOptions o;
  o.set_frame(args.get("frame"));
  if (args.has("voxel")) o.set_voxel_size_m(parse_positive(args.get("voxel"), "--voxel"));
  if (args.has("crop")) {
    std::vector<double> v;
    std::stringstream text(args.get("crop"));
    for (std::string item; std::getline(text, item, ',');) {
      try {
        size_t used = 0;
        v.push_back(std::stod(item, &used));
        if (used != item.size()) throw std::invalid_argument(item);
      } catch (const std::exception&) {
        throw UsageError("--crop: '" + item + "' is not a number (expected X0,Y0,Z0,X1,Y1,Z1 in metres)");
      }
    }
    if (v.size() != 6) throw UsageError("--crop: expected six numbers X0,Y0,Z0,X1,Y1,Z1, got " + std::to_string(v.size()));
    auto* c = o.mutable_crop();
    c->mutable_min()->set_x(v[0]);
    c->mutable_min()->set_y(v[1]);
    c->mutable_min()->set_z(v[2]);
    c->mutable_max()->set_x(v[3]);
    c->mutable_max()->set_y(v[4]);
    c->mutable_max()->set_z(v[5]);
  }
  if (args.has("fusion")) {
    const std::string f = args.get("fusion");
    if (f == "nearest") o.set_fusion(v1::NEAREST_CENTRE);
    else if (f == "blend") o.set_fusion(v1::BLEND);
    else throw UsageError("--fusion: expected nearest or blend, got '" + f + "'");
  }
  if (args.has("no-occlusion")) o.set_occlusion(false);
  return o;
}

// OUT.ply -> OUT_000007.ply
std::string numbered(const std::string& path, uint64_t index) {
  const std::filesystem::path p(path);
  std::ostringstream name;
  name << p.stem().string() << "_" << std::setw(6) << std::setfill('0') << index << p.extension().string();
  return (p.parent_path() / name.str()).string();
}

void save(const v1::PointCloud& message, const std::string& path, bool coloured_only) {
  PointCloud cloud = cloud_from_message(message);
  if (coloured_only && !cloud.flags.empty()) {
    std::vector<bool> keep(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) keep[i] = cloud.flags[i] & cloud_flags::kColoured;
    cloud.filter(keep);
  }
  // As `record -o`: the folder the user named is made (scans/scan.ply into a new scans/).
  if (const auto folder = std::filesystem::path(path).parent_path(); !folder.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    if (ec) throw std::runtime_error(folder.string() + ": cannot make the folder: " + ec.message());
  }
  save_cloud(cloud, path);
  const auto& c = message.counts();
  std::cout << path << ": " << cloud.size() << " points in '" << message.frame() << "' (of " << message.input_points()
            << " from source '" << message.source() << "'); of the " << message.point_count()
            << " the daemon sent: coloured " << c.coloured() << ", occluded "
            << c.occluded() << ", self-filtered " << c.self_filtered() << ", unseen " << c.unseen()
            << "; sequence " << message.sequence() << ", captured " << format_time(message.stamp()) << ", coloured in "
            << fixed(message.colour_ms(), 1) << " ms\n";
  if (cloud.size() == 0 && message.input_points() > 0) {
    std::cerr << "omniview cloud: " << path << " holds no point: "
              << (message.point_count() == 0 ? "the crop box (--crop, in --frame) left none"
                                              : "no point was coloured (--coloured-only)")
              << "\n";
  }
}

}  // namespace

int cloud_command(const std::vector<std::string>& argv) {
  const auto args = parse_command_args(argv, {"follow", "no-occlusion", "coloured-only"},
                                       {"output", "count", "frame", "voxel", "crop", "fusion", "rate", "wait"}, kCloudHelp);
  if (!args) return 0;
  if (args->positional().size() > 1) throw UsageError("expected at most one SOURCE, got " + std::to_string(args->positional().size()));
  const std::string source = args->positional().empty() ? "" : args->positional()[0];
  const std::string output = args->required("output");
  const std::string ext = std::filesystem::path(output).extension().string();
  if (ext != ".ply" && ext != ".pcd") throw UsageError("-o: '" + output + "' should end in .ply or .pcd");
  if (args->has("count") && args->has("follow")) throw UsageError("--count and --follow: choose one");
  const bool coloured_only = args->has("coloured-only");
  Connection connection(connection_options(*args));

  if (!args->has("count") && !args->has("follow")) {
    if (args->has("rate")) throw UsageError("--rate is for --count and --follow");
    double wait_s = 5;
    if (args->has("wait")) wait_s = parse_positive(args->get("wait"), "--wait");
    v1::GetCloudRequest request;
    request.set_source(source);
    *request.mutable_options() = cloud_options(*args);
    request.set_timeout_ms(static_cast<int>(wait_s * 1000));
    grpc::ClientContext context;
    connection.prepare(context, true);
    context.set_deadline(std::chrono::system_clock::now() + connection.options().deadline +
                         std::chrono::milliseconds(static_cast<int64_t>(wait_s * 1000)));
    v1::PointCloud message;
    connection.check(connection.stub().GetCloud(&context, request, &message), "the cloud of " + (source.empty() ? std::string("the first source") : "source '" + source + "'"));
    save(message, output, coloured_only);
    return 0;
  }

  const int count = args->has("count") ? parse_count(args->get("count"), "--count") : 0;
  v1::StreamCloudsRequest request;
  request.set_source(source);
  *request.mutable_options() = cloud_options(*args);
  if (args->has("rate")) request.set_max_rate_hz(parse_positive(args->get("rate"), "--rate"));
  grpc::ClientContext context;
  connection.prepare(context, false);
  StreamStopper stopper(context, 0);
  auto reader = connection.stub().StreamClouds(&context, request);
  v1::PointCloud message;
  uint64_t saved = 0;
  while ((count == 0 || saved < static_cast<uint64_t>(count)) && reader->Read(&message)) {
    save(message, numbered(output, ++saved), coloured_only);
  }
  if (count > 0 && saved == static_cast<uint64_t>(count)) stopper.stop();  // the daemon ends the call on the cancel
  const grpc::Status status = reader->Finish();
  const bool failed = !status.ok() && !(stopper.stopped() && status.error_code() == grpc::StatusCode::CANCELLED);
  std::cout << saved << " cloud(s) saved\n";
  if (failed) {
    connection.check(status, "the clouds of " + (source.empty() ? std::string("the first source") : "source '" + source + "'"));
  }
  if (count > 0 && saved < static_cast<uint64_t>(count)) return stopper.interrupted() ? 130 : 1;
  return stopper.interrupted() ? 130 : 0;
}

}  // namespace omniview::cli
