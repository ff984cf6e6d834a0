#include "server/daemon/daemon.h"

#include <algorithm>

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <grpcpp/server_builder.h>

#include "core/robot/model/urdf_loader.h"
#include "server/auth/server_credentials.h"
#include "server/exposure/exposure_rule.h"
#include "server/exposure/host_port.h"
#include "server/source/source_registry.h"
#include "server/web/web_server.h"

namespace omniview {

namespace {

// "host:port" with the port replaced; a unix socket's address as it is.
std::string with_port(const std::string& listen, int port) {
  if (is_unix_address(listen)) return listen;
  const auto colon = listen.rfind(':');
  return listen.substr(0, colon + 1) + std::to_string(port);
}

// The URDF with its meshes, and the config's joint positions checked against it.
std::shared_ptr<const RobotModelSetup> load_robot_model(const RobotModelEntry& entry) {
  auto setup = std::make_shared<RobotModelSetup>();
  setup->model = std::make_shared<const robot::RobotModel>(
      robot::load_urdf_file(entry.urdf_file, robot::MeshSearchPath({entry.mesh_path.begin(), entry.mesh_path.end()})));
  auto positions = setup->model->zero_positions();
  setup->model->apply(entry.joints, positions);  // names a joint the URDF lacks: an error here
  setup->model->check_limits(entry.joints);      // and a position beyond the URDF's limits
  setup->frame = entry.frame;
  setup->fixed_joints = entry.joints;
  setup->style.outline_px = entry.outline_px;
  return setup;
}

// robot_models[].frame must be a frame of the source's rig: a typo would otherwise only
// show as a robot missing from the views (and a line in the log).
void check_robot_model_frame(const RobotModelEntry& entry, const Rig& rig, const YamlReader& reader) {
  if (entry.frame.empty()) return;
  const auto known = rig.known_frames();
  if (std::find(known.begin(), known.end(), entry.frame) != known.end()) return;
  std::string list;
  for (const auto& f : known) list += (list.empty() ? "" : ", ") + f;
  reader.fail(entry.node["frame"] ? entry.node["frame"] : entry.node, entry.path + ".frame",
              "source '" + entry.source + "' has no frame '" + entry.frame + "' (its frames: " + list + ")");
}

}  // namespace

Daemon::Daemon(const DaemonConfig& config, bool listen) : config_(config) {
  const YamlReader& reader = *config_.reader;
  // The exposure rule once more where the address is used: --check and a start ask it alike,
  // whoever built the config.
  check_listen_exposure(config_);
  check_rtsp_exposure(config_);
  check_web_exposure(config_);
  PipelineLimits limits;
  limits.max_view_pixels = config_.limits.max_view_pixels;
  limits.max_views = config_.limits.max_views;
  limits.record_queue.max_frame_sets = static_cast<size_t>(config_.limits.record_queue_frame_sets);
  limits.record_queue.max_bytes = static_cast<size_t>(config_.limits.record_queue_mb) << 20;
  pipeline_ = std::make_unique<Pipeline>(limits);

  for (const auto& s : config_.sources) {
    SourceConfig sc{s.name, &reader, s.node, s.path, config_.folder};
    try {
      pipeline_->add_source(make_source(s.type, sc));
    } catch (const ConfigError& e) {
      // Errors the factory found in this config already name it; errors in files the
      // source loads (its rig, say) also get pointed at the entry that named them.
      if (std::string(e.what()).rfind(reader.file(), 0) == 0) throw;
      reader.fail(s.node, s.path, "source '" + s.name + "' cannot start: " + e.what());
    } catch (const std::exception& e) {
      reader.fail(s.node, s.path, "source '" + s.name + "' cannot start: " + e.what());
    }
  }
  for (const auto& m : config_.robot_models) {
    check_robot_model_frame(m, *pipeline_->rig(m.source), reader);
    try {
      pipeline_->set_robot_model(m.source, load_robot_model(m));
    } catch (const std::exception& e) {
      reader.fail(m.node, m.path, "robot model for source '" + m.source + "': " + e.what());
    }
  }
  for (size_t i = 0; i < config_.views.size(); ++i) {
    const ViewSpec& spec = config_.views[i];
    try {
      pipeline_->create_view(spec);
    } catch (const std::exception& e) {
      const YAML::Node list = reader.root()["views"];
      reader.fail(list && list.IsSequence() ? list[i] : reader.root(), "views[" + std::to_string(i) + "]", e.what());
    }
  }

  if (config_.blackbox) {
    const YAML::Node box = reader.root()["blackbox"];
    try {
      if (listen) {
        std::vector<std::string> sources;
        for (const auto& s : config_.sources) sources.push_back(s.name);
        black_box_ = std::make_unique<BlackBox>(*config_.blackbox, *pipeline_, sources);
      } else {
        BlackBox::check_folder(config_.blackbox->folder);  // --check leaves a ring as it is
      }
    } catch (const std::exception& e) {
      reader.fail(box && box["folder"] ? box["folder"] : box, "blackbox.folder", e.what());
    }
  }

  auth_ = std::make_unique<Authenticator>(config_.tokens);
  service_ = std::make_unique<OmniviewService>(*pipeline_, *auth_, config_.limits);
  service_->set_black_box(black_box_.get());
  const auto credentials = make_server_credentials(config_.tls);
  if (!listen) return;

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(config_.listen, credentials, &port);
  builder.RegisterService(service_.get());
  builder.SetMaxReceiveMessageSize(config_.limits.max_message_bytes);
  builder.SetMaxSendMessageSize(config_.limits.max_message_bytes);
  // The sync server runs a thread per call in flight: bound it so a flood of clients is
  // refused (RESOURCE_EXHAUSTED) instead of exhausting the machine.
  grpc::ResourceQuota quota("omniviewd");
  quota.SetMaxThreads(config_.limits.max_streams + 64);
  builder.SetResourceQuota(quota);
  // Notice vanished clients (Wi-Fi gone) within ~20 s rather than the TCP default.
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS, 5000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  // gRPC sets SO_REUSEPORT by default: a second daemon on the same port would then start
  // and silently share the traffic. Refuse instead.
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  server_ = builder.BuildAndStart();
  if (!server_ || port == 0) {
    const std::string why =
        "cannot listen on '" + config_.listen + "' (address in use, or not an address of this machine?)";
    if (!config_.listen_from.empty()) throw ConfigError(config_.listen_from + ": " + why);
    const YAML::Node listen = reader.root()["listen"];
    reader.fail(listen ? listen : reader.root(), "listen", why);
  }
  try {
    restrict_unix_socket(config_.listen);  // owner and group only, whatever the umask
  } catch (const std::exception& e) {
    server_->Shutdown();
    throw ConfigError(std::string("listen: ") + e.what());
  }
  // Health by service name too (grpc_health_probe -service=omniview.v1.Omniview).
  server_->GetHealthCheckService()->SetServingStatus(v1::Omniview::service_full_name(), true);
  address_ = with_port(config_.listen, port);
  if (config_.web.enabled) {
    try {
      web_ = std::make_unique<web::WebServer>(config_, *pipeline_, *auth_);
    } catch (...) {
      server_->Shutdown();
      throw;
    }
  }
  pipeline_->start();
  if (config_.rtsp) {
    try {
      rtsp_ = std::make_unique<RtspServer>(config_, *pipeline_);
    } catch (const std::exception& e) {
      shutdown();
      const YAML::Node rtsp = reader.root()["rtsp"];
      reader.fail(rtsp ? rtsp : reader.root(), "rtsp", e.what());
    }
  }
}

std::vector<std::string> Daemon::rtsp_urls() const { return rtsp_ ? rtsp_->urls() : std::vector<std::string>{}; }

Daemon::~Daemon() { shutdown(); }

std::string Daemon::web_url() const { return web_ ? web_->url() : ""; }
std::string Daemon::whep_summary() const { return web_ ? web_->whep_summary() : ""; }
std::string Daemon::web_address() const { return web_ ? web_->address() : ""; }

void Daemon::shutdown(std::chrono::milliseconds grace) {
  if (shut_down_) return;
  shut_down_ = true;
  if (server_) server_->GetHealthCheckService()->Shutdown();  // health: NOT_SERVING from now on
  if (rtsp_) rtsp_->stop();  // its clients' feeds leave the pipeline first
  if (web_) web_->stop();  // browsers told "shutting down" (close 1001) before their streams end
  if (black_box_) black_box_->stop();  // its open segments closed whole
  // Streams end first (their handlers return UNAVAILABLE), so Shutdown has little to wait for.
  pipeline_->stop("omniviewd is shutting down");
  if (server_) {
    server_->Shutdown(std::chrono::system_clock::now() + grace);
    server_->Wait();
  }
}

}  // namespace omniview
