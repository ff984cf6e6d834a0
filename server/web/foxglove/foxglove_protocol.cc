#include "server/web/foxglove/foxglove_protocol.h"

#include <chrono>

#include "server/pipeline/cloud/cloud_request.h"
#include "server/pipeline/frame_encoder.h"
#include "server/video/h264_encoder.h"
#include "server/web/foxglove/foxglove_messages.h"
#include "server/web/foxglove/foxglove_sources.h"

namespace omniview::web {

namespace {

constexpr auto kReadvertisePeriod = std::chrono::seconds(2);

// Whether a view's size can be H.264 (not beyond its largest picture): others get no video channel.
bool h264_size(int width, int height) {
  video::H264Settings settings;
  settings.width = width;
  settings.height = height;
  try {
    video::check(settings);
    return true;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

std::string channel_json(uint32_t id, const std::string& topic, const google::protobuf::Descriptor* type) {
  return "{\"id\":" + std::to_string(id) + ",\"topic\":" + json::quote(topic) +
         ",\"encoding\":\"protobuf\",\"schemaName\":" + json::quote(type->full_name()) +
         ",\"schemaEncoding\":\"protobuf\",\"schema\":" + json::quote(foxglove_io::schema_base64(type)) + "}";
}

}  // namespace

FoxgloveProtocol::FoxgloveProtocol(std::weak_ptr<Connection> connection, const WebContext& context, Caller caller)
    : connection_(std::move(connection)), context_(context), caller_(std::move(caller)) {
  if (const auto c = connection_.lock()) peer_ = c->peer();
}

FoxgloveProtocol::~FoxgloveProtocol() { on_close(); }

void FoxgloveProtocol::send(std::string text) {
  if (const auto c = connection_.lock()) c->send_text(std::move(text));
}

void FoxgloveProtocol::status(int level, const std::string& message) {
  send("{\"op\":\"status\",\"level\":" + std::to_string(level) + ",\"message\":" + json::quote(message) + "}");
}

void FoxgloveProtocol::on_open() {
  // No capabilities: clients may only subscribe (no publishing, parameters or services).
  send(std::string("{\"op\":\"serverInfo\",\"name\":\"omniviewd ") + OMNIVIEW_VERSION +
       "\",\"capabilities\":[],\"supportedEncodings\":[],\"metadata\":{\"role\":" +
       json::quote(to_string(caller_.role)) + "},\"sessionId\":" +
       json::quote(std::to_string(std::chrono::system_clock::now().time_since_epoch().count())) + "}");
  advertise();
}

void FoxgloveProtocol::advertise() {
  struct Wanted {
    Kind kind;
    std::string target;
    const google::protobuf::Descriptor* type;
  };
  std::map<std::string, Wanted> wanted;  // by topic
  for (const auto& view : context_.pipeline.list_views()) {
    const std::string& name = view.spec().name();
    wanted["/" + name + "/image"] = {Kind::kImage, name, foxglove::CompressedImage::descriptor()};
    // Beside the JPEG channel, for clients that decode H.264 (a fraction of the bits).
    if (h264_size(view.spec().width(), view.spec().height())) {
      wanted["/" + name + "/video"] = {Kind::kVideo, name, foxglove::CompressedVideo::descriptor()};
    }
    if (view.intrinsics_size() == 4) {
      wanted["/" + name + "/calibration"] = {Kind::kCalibration, name, foxglove::CameraCalibration::descriptor()};
    }
  }
  for (const auto& source : context_.pipeline.report().sources) {
    if (context_.pipeline.provides_clouds(source.name)) {
      wanted["/" + source.name + "/cloud"] = {Kind::kCloud, source.name, foxglove::PointCloud::descriptor()};
    }
  }
  wanted["/tf"] = {Kind::kTransforms, "", foxglove::FrameTransforms::descriptor()};

  // Channels of views deleted (or renamed) since: unadvertised, their subscriptions ended.
  std::string gone;
  for (auto it = channels_.begin(); it != channels_.end();) {
    const auto w = wanted.find(it->second.topic);
    if (w != wanted.end() && w->second.kind == it->second.kind) {
      wanted.erase(w);  // still there: advertised already
      ++it;
      continue;
    }
    std::erase_if(subscriptions_, [&](const auto& entry) { return entry.second.channel == it->first; });
    gone += (gone.empty() ? "" : ",") + std::to_string(it->first);
    it = channels_.erase(it);
  }
  if (!gone.empty()) send("{\"op\":\"unadvertise\",\"channelIds\":[" + gone + "]}");
  std::string list;
  for (const auto& [topic, w] : wanted) {
    const uint32_t id = next_channel_++;
    channels_[id] = Channel{w.kind, w.target, topic, w.type->full_name()};
    list += (list.empty() ? "" : ",") + channel_json(id, topic, w.type);
  }
  if (!list.empty()) send("{\"op\":\"advertise\",\"channels\":[" + list + "]}");
  // Views come and go at run time (CreateView, DeleteView): look again in a while.
  if (const auto c = connection_.lock()) c->after(kReadvertisePeriod, [this] { advertise(); });
}

void FoxgloveProtocol::on_message(std::string_view data, bool binary) {
  if (binary) {
    return status(2, "binary client messages (publishing, service calls) are not supported by omniviewd");
  }
  std::string error;
  const auto message = json::parse_object(data, &error);
  if (!message) return status(2, error);
  try {
    const auto op = json::string_field(*message, "op");
    if (!op) return status(2, "message has no 'op'");
    if (*op == "subscribe") return subscribe(*message);
    if (*op == "unsubscribe") return unsubscribe(*message);
    status(2, "op '" + *op + "' is not supported by omniviewd (it serves subscribe and unsubscribe)");
  } catch (...) {
    status(2, current_failure().message);
  }
}

void FoxgloveProtocol::subscribe(const json::Value& message) {
  const json::Value* list = json::find(message, "subscriptions");
  if (!list || !list->is_array()) throw std::invalid_argument("'subscribe' needs a 'subscriptions' list");
  for (const auto& entry : *list) {
    if (!entry.is_object()) {
      status(2, "each subscription must be an object {id, channelId}");
      continue;
    }
    try {
      const auto id = json::integer_field(entry, "id", 0, UINT32_MAX);
      const auto channel = json::integer_field(entry, "channelId", 0, UINT32_MAX);
      if (!id || !channel) {
        status(2, "a subscription needs 'id' and 'channelId'");
        continue;
      }
      start(static_cast<uint32_t>(*id), static_cast<uint32_t>(*channel));
    } catch (...) {
      status(2, current_failure().message);
    }
  }
}

void FoxgloveProtocol::unsubscribe(const json::Value& message) {
  const json::Value* list = json::find(message, "subscriptionIds");
  if (!list || !list->is_array()) throw std::invalid_argument("'unsubscribe' needs a 'subscriptionIds' list");
  for (const auto& v : *list) {
    if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= UINT32_MAX)) {
      status(2, "subscription ids are numbers");
      continue;
    }
    const auto id = static_cast<uint32_t>(v.get<double>());
    if (!subscriptions_.count(id)) {
      status(1, "no subscription " + std::to_string(id));
      continue;
    }
    subscriptions_.erase(id);  // Stream's end stops its pump and leaves the pipeline
  }
}

void FoxgloveProtocol::start(uint32_t id, uint32_t channel_id) {
  const auto ch = channels_.find(channel_id);
  if (ch == channels_.end()) {
    return status(2, "no channel " + std::to_string(channel_id) + " (see the advertise message)");
  }
  if (subscriptions_.count(id)) return status(2, "subscription id " + std::to_string(id) + " is already in use");
  // The per-connection cap is on what costs an encode or a colouring (images, video,
  // clouds); a view's calibration and the transforms ride along, so a client that subscribes
  // to every topic (as Foxglove's panels do) still gets /tf and the calibrations. Those are
  // bounded by the channels there are.
  const auto costly = [](Kind k) { return k == Kind::kImage || k == Kind::kVideo || k == Kind::kCloud; };
  size_t costly_count = 0;
  for (const auto& entry : subscriptions_) {
    const auto it = channels_.find(entry.second.channel);  // a channel gone since counts as costly
    if (it == channels_.end() || costly(it->second.kind)) ++costly_count;
  }
  const size_t light_count = subscriptions_.size() - costly_count;
  if (costly(ch->second.kind) && static_cast<int>(costly_count) >= context_.limits.max_streams_per_client) {
    return status(2, "at most " + std::to_string(context_.limits.max_streams_per_client) +
                         " image, video and cloud subscriptions per connection (limits.max_streams_per_client)");
  }
  if (!costly(ch->second.kind) && light_count >= channels_.size()) {
    return status(2, "at most one subscription per calibration or transforms channel");
  }
  const Channel channel = ch->second;
  const std::string peer = peer_ + " (foxglove)";
  Pump::Source source;
  std::function<void()> release;
  if (channel.kind == Kind::kImage || channel.kind == Kind::kVideo || channel.kind == Kind::kCalibration) {
    // The default quality: the encoding most clients share, so usually no extra encode. A
    // video subscriber joins its group's one encoder at a key frame, and after a frame it
    // could not take skips to the next key frame (Subscriber), so no broken picture.
    const v1::Encoding encoding = channel.kind == Kind::kVideo ? v1::H264 : v1::JPEG;
    auto subscription =
        context_.pipeline.subscribe(channel.target, peer, encoding_key(encoding, 0, false), context_.limits.max_rate_hz);
    const std::string frame_id = foxglove_io::view_optical_frame(channel.target);
    source = subscriber_source(subscription.shared(), foxglove_io::frame_data(id, channel.kind, frame_id),
                               foxglove_io::ended_status<Subscriber>(connection_, channel.topic));
    release = release_of(std::move(subscription));
  } else if (channel.kind == Kind::kCloud) {
    v1::CloudOptions options;
    options.set_voxel_size_m(0.05);  // a few cm: what a 3D panel shows well, a tenth of the bytes
    auto subscription = context_.pipeline.subscribe_cloud(channel.target, peer, cloud_request_from_proto(options),
                                                          std::min(10.0, context_.limits.max_rate_hz));
    source = subscriber_source(subscription.shared(),
                               [id](const SharedCloud& cloud) { return foxglove_io::cloud_data(id, cloud); },
                               foxglove_io::ended_status<CloudSubscriber>(connection_, channel.topic));
    release = release_of(std::move(subscription));
  } else {
    source = foxglove_io::transforms_source(id, context_.pipeline);
  }
  subscriptions_.try_emplace(id, channel_id, connection_, id, std::move(source), std::move(release));
}

void FoxgloveProtocol::on_close() {
  if (closed_) return;
  closed_ = true;
  subscriptions_.clear();
}

}  // namespace omniview::web
