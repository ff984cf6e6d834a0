// omniviewd's configuration file (see config/omniviewd.yaml for a commented example).
//
//   listen: 127.0.0.1:50051
//   tls: {cert: server.crt, key: server.key, client_ca: clients.crt}   # optional
//   tokens:                                                           # optional
//     - {role: operator, token_file: operator.token}    # or token_env: NAME, or token: TEXT
//     - {role: viewer, token_file: viewer.token}
//   allow_insecure_remote: false   # plaintext on a non-loopback address needs this
//   limits: {max_view_pixels, max_views, max_streams_per_client, max_streams,
//            max_message_bytes, max_rate_hz, record_queue_frame_sets, record_queue_mb}
//   sources:
//     - {name: examples, type: images, ...}          # the type's own keys, see source types
//   views:                                            # the view YAML schema, plus `source`
//     - {name: front, type: perspective, ...}
//   views_file: saved_views.yaml                      # optional: `omniview views save` output
//   rtsp: {listen: 127.0.0.1:8554, quality: 0, max_bitrate_kbps: 0, max_rate_hz: 0}  # optional
//   robot_models:                                     # optional: the robot drawn into views
//     - {source: spot, urdf: robot.urdf, mesh_path: [meshes], frame: body, joints: {...}}
//   blackbox: {minutes: 5, max_bytes: 2G, folder: blackbox}   # optional: the last minutes on disk
//
// Relative paths resolve against the config file's folder. Every error names the file, the
// line and the key, and the daemon refuses to start.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/io/yaml_reader.h"
#include "core/view/view_spec.h"
#include "server/exposure/exposure_rule.h"

namespace omniview {

enum class Role { kViewer, kOperator };
std::string to_string(Role role);

struct TlsConfig {
  std::string cert_file;       // PEM server certificate (chain)
  std::string key_file;        // PEM private key
  std::string client_ca_file;  // optional: require client certificates signed by it
};

struct TokenConfig {
  std::string token;  // the secret itself (read from token_file/token_env at load time)
  Role role = Role::kViewer;
  std::string label;  // where it came from ("tokens[1] (operator.token)"), for logs; never the secret
};

struct Limits {
  int64_t max_view_pixels = 4096LL * 4096;  // width * height of one view
  int max_views = 32;
  int max_streams_per_client = 8;           // concurrent frame streams from one peer
  int max_streams = 64;                     // concurrent frame streams in all
  int max_message_bytes = 64 << 20;         // largest gRPC message either way
  double max_rate_hz = 60;                  // cap on a stream's max_rate_hz
  int record_queue_frame_sets = 32;         // queued per recording client before it skips
  int record_queue_mb = 256;                // and the MiB of images those may hold
};

// `web:` — the HTTP + WebSocket endpoint (server/web): the operator console and the
// Foxglove WebSocket protocol, with the gRPC API's TLS certificate and tokens.
// `web.webrtc:` — the views over WebRTC (WHEP: POST /whep/VIEW) on the web port
// (server/webrtc). Media flows over UDP between the viewer and the daemon (ICE).
struct WebRtcConfig {
  bool enabled = true;
  std::string stun_server;  // "stun://host:port": a server-reflexive candidate for NATs (empty: none)
  std::string turn_server;  // "turn://user:password@host:port": a relay where UDP cannot pass (empty: none)
  int min_udp_port = 0;     // udp_ports "MIN-MAX": the media's ports, for a firewall (0: any)
  int max_udp_port = 0;
  int max_sessions = 16;    // viewers at once, in all and from one address
  int max_sessions_per_client = 4;
  int quality = 0;          // as StreamFramesRequest.quality for H264 (0: default)
  int max_bitrate_kbps = 0; // as StreamFramesRequest.max_bitrate_kbps (0: none)
};

struct WebConfig {
  bool enabled = false;
  std::string listen = "127.0.0.1:8765";  // host:port (8765: what Foxglove clients try first)
  std::string console_dir;                // empty: the installed console, else the source tree's
  std::string javascript_dir = "/usr/share/javascript";  // Debian's JS libraries (libjs-three)
  // WebSocket and HTTP connections at once (a browser keeps ~6 HTTP connections per page
  // open a while, so room for a few pages each).
  int max_connections = 64;
  int max_message_bytes = 64 << 10;       // largest message a client may send
  int max_pending_bytes = 16 << 20;       // unsent replies to one client before it is dropped
  YAML::Node listen_node;                 // for errors found at start (address in use)
  WebRtcConfig webrtc;
};

struct SourceEntry {
  std::string name;
  std::string type;
  YAML::Node node;   // the source's map (its type's keys are read by the source factory)
  std::string path;  // YAML path, e.g. "sources[0]"
};

// A robot drawn into the views of one source (views with `overlay: true`).
struct RobotModelEntry {
  std::string source;                  // whose views
  std::string urdf_file;               // resolved against the config's folder
  std::vector<std::string> mesh_path;  // folders for package:// and relative mesh URIs
  std::string frame;                   // the rig frame the URDF's root link sits at (empty: the rig's own)
  std::map<std::string, double> joints;  // positions of joints the source does not report
  int outline_px = 1;
  YAML::Node node;   // for errors found when the model loads
  std::string path;  // e.g. "robot_models[0]"
};

// `rtsp:` — every view also as rtsp://HOST:PORT/VIEW (server/rtsp), H.264 from the same
// shared encoders as gRPC's H264 streams. Off unless the block is there.
struct RtspConfig {
  std::string listen = "127.0.0.1:8554";  // host:port (port 0: a free one, for tests)
  int quality = 0;                         // as StreamFramesRequest.quality for H264 (0: default)
  int max_bitrate_kbps = 0;                // as StreamFramesRequest.max_bitrate_kbps (0: none)
  double max_rate_hz = 0;                  // 0: as the source delivers (within limits.max_rate_hz)
  // Connections at once, in all and from one client address: each may hold a prepared
  // media (a GStreamer pipeline and its threads), so the excess is closed at accept.
  int max_connections = 32;
  int max_connections_per_client = 8;
  // A connection that has no stream playing (never authenticated, DESCRIBE only, paused)
  // is closed after this many seconds, so that it cannot hold its slot.
  int idle_timeout_s = 20;
};

// `blackbox:` — the daemon keeps the last `minutes` of what its sources deliver (camera
// images, clouds, joints, rig) in a ring on disk of at most `max_bytes`, and saves it as an
// ordinary recording on request or when a robot's connection drops (server/blackbox).
struct BlackBoxConfig {
  double minutes = 5;
  uint64_t max_bytes = uint64_t{2} << 30;
  std::string folder;  // resolved; the ring is folder/ring/<source>, snapshots folder/snapshots/<name>
  YAML::Node node;     // for errors found at start (an unwritable folder)
};

struct DaemonConfig {
  std::string file;    // the config file, for messages
  std::string folder;  // relative paths resolve against it
  std::string listen = "127.0.0.1:50051";  // the effective address (see ListenOptions)
  std::string listen_from;                  // "" (the file, or the default), "--listen" or "OMNIVIEW_LISTEN"
  std::optional<TlsConfig> tls;
  std::vector<TokenConfig> tokens;  // empty: no authentication (every caller is an operator)
  bool allow_insecure_remote = false;
  Limits limits;
  std::vector<SourceEntry> sources;  // at least one
  std::vector<ViewSpec> views;       // each view's `source` is set (defaults to the first source)
  std::vector<RobotModelEntry> robot_models;
  std::shared_ptr<const YamlReader> reader;  // keeps the nodes above readable, for errors
  // `views_file:` (resolved; empty: none): views saved with `omniview views save`, loaded
  // over `views` at start (same name: the file's wins). A file not there yet is no error.
  std::string views_file;
  std::optional<RtspConfig> rtsp;
  WebConfig web;
  std::optional<BlackBoxConfig> blackbox;
};

// Where the listen address may come from besides the file, strongest first: the --listen
// flag, then the OMNIVIEW_LISTEN environment variable (set and not empty), then the file's
// `listen`, then 127.0.0.1:50051.
struct ListenOptions {
  std::optional<std::string> flag;
  std::optional<std::string> env;
  HostResolver resolve;  // how host names resolve (empty: getaddrinfo); tests and fuzzing pass their own
  // `flag` as given, and OMNIVIEW_LISTEN from this process's environment.
  static ListenOptions from_environment(std::optional<std::string> flag);
};

// Loads and checks a config file: keys, types, files that must exist, roles, limits, view
// definitions (validated, and within the limits), unique source and view names; then the
// listen address overrides in `listen`, and the exposure rule (server/exposure) on the
// effective address. Throws ConfigError "file:line: key: message", or "--listen: message" /
// "OMNIVIEW_LISTEN: message" when the override is at fault.
DaemonConfig load_daemon_config(const std::string& path, const ListenOptions& listen = {});
DaemonConfig parse_daemon_config(const YamlReader& reader, const std::string& folder, const ListenOptions& listen = {});

// The exposure rule on the web endpoint's address (`web.listen`), when it is enabled:
// the same rule, the same TLS and tokens as the gRPC API. Throws ConfigError.
void check_web_exposure(const DaemonConfig& config, const HostResolver& resolve = {});

// The exposure rule on the config's effective listen address, blaming the file's `listen`
// line or the override it came from. Throws ConfigError. Config loading and the daemon's
// start both call it (an address's reach can change between the two: a folder's mode).
void check_listen_exposure(const DaemonConfig& config, const HostResolver& resolve = {});
// The same rule on `rtsp.listen` (the same tls and tokens guard it), blaming that line.
void check_rtsp_exposure(const DaemonConfig& config, const HostResolver& resolve = {});

// --- Additions -------------------------------------------------------------------------
// Paths in TlsConfig are stored resolved against the config's folder.

// "viewer" | "operator"; throws std::invalid_argument naming the accepted values.
Role role_from_string(const std::string& name);
// An operator may do everything a viewer may.
bool role_allows(Role granted, Role needed);

// Checks the form of a listen address ("host:port", "[v6]:port", "unix:PATH"); returns an
// empty string when fine, else what is wrong (for a message).
std::string listen_address_problem(const std::string& listen);

// `path` resolved against `folder` unless it is absolute.
std::string resolve_config_path(const std::string& folder, const std::string& path);

}  // namespace omniview
