#include "server/api/omniview_service.h"

#include <chrono>
#include <iostream>
#include <sstream>

#include <google/protobuf/util/time_util.h>

#include "core/cloud/cloud_file.h"
#include "core/io/image_codec.h"
#include "core/rig/rig.h"
#include "server/api/request_bounds.h"
#include "server/api/service_support.h"
#include "server/api/status_message.h"
#include "server/convert/convert.h"
#include "server/pipeline/frame_encoder.h"

namespace omniview {

namespace {

using service_support::guarded;
using service_support::closed_status;

// A frame set as StreamSourceFrames sends it: the source's encoded bytes where it kept
// them (a robot's JPEG: no loss, no work), lossless PNG otherwise.
v1::SourceFrame to_source_frame(const FrameSet& frames, uint64_t skipped_before, bool with_rig) {
  v1::SourceFrame out;
  out.set_sequence(frames.sequence);
  out.set_skipped(skipped_before);
  *out.mutable_capture_time() = google::protobuf::util::TimeUtil::NanosecondsToTimestamp(
      std::chrono::duration_cast<std::chrono::nanoseconds>(frames.capture_time.time_since_epoch()).count());
  if (with_rig) out.set_rig_yaml(rig_to_yaml(*frames.rig));
  if (frames.joints) out.mutable_joint_positions()->insert(frames.joints->begin(), frames.joints->end());
  if (frames.cloud) out.set_cloud_pcd(format_pcd(*frames.cloud, CloudEncoding::kBinary));
  const auto& cams = frames.rig->cameras();
  for (size_t i = 0; i < frames.images.size() && i < cams.size(); ++i) {
    const cv::Mat& img = frames.images[i];
    if (img.empty()) continue;
    auto* image = out.add_images();
    image->set_camera(cams[i].name);
    image->set_width(img.cols);
    image->set_height(img.rows);
    image->set_channels(img.channels());
    const EncodedImage* encoded = i < frames.encoded.size() ? &frames.encoded[i] : nullptr;
    if (encoded && encoded->bytes && (encoded->format == "jpeg" || encoded->format == "png")) {
      image->set_encoding(encoded->format == "png" ? v1::PNG : v1::JPEG);
      image->set_data(encoded->bytes->data(), encoded->bytes->size());
      continue;
    }
    std::vector<uint8_t> png;
    try {
      png = encode_png(img);
    } catch (const std::exception& e) {
      throw std::runtime_error("the image of camera '" + cams[i].name + "': " + e.what());
    }
    image->set_encoding(v1::PNG);
    image->set_data(png.data(), png.size());
  }
  return out;
}

v1::JointPositions to_proto(const JointsReport& report) {
  v1::JointPositions out;
  out.set_source(report.source);
  out.set_robot(report.robot);
  for (const JointReport& j : report.joints) {
    v1::Joint* joint = out.add_joints();
    joint->set_name(j.name);
    joint->set_position(j.position);
    joint->set_unit(j.unit);
    using Origin = JointReport::Origin;
    joint->set_origin(j.origin == Origin::kConfig ? v1::Joint::CONFIG
                      : j.origin == Origin::kApi  ? v1::Joint::API
                      : j.origin == Origin::kSource ? v1::Joint::SOURCE
                                                   : v1::Joint::URDF_ZERO);
  }
  return out;
}

}  // namespace

grpc::Status OmniviewService::acquire_stream(const std::string& peer) {
  std::lock_guard lock(streams_mutex_);
  if (streams_ >= limits_.max_streams) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "omniviewd is serving its maximum of " + std::to_string(limits_.max_streams) +
                            " streams (limits.max_streams); try again later");
  }
  int& mine = streams_per_peer_[peer];
  if (mine >= limits_.max_streams_per_client) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "this connection already has " + std::to_string(mine) +
                            " streams open (limits.max_streams_per_client); close one first");
  }
  ++mine;
  ++streams_;
  return grpc::Status::OK;
}

void OmniviewService::release_stream(const std::string& peer) {
  std::lock_guard lock(streams_mutex_);
  if (--streams_per_peer_[peer] <= 0) streams_per_peer_.erase(peer);
  --streams_;
}

grpc::Status OmniviewService::ListCameras(grpc::ServerContext* ctx, const v1::ListCamerasRequest* req,
                                          v1::ListCamerasResponse* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    for (const SourceCamera& c : pipeline_.cameras(req->source())) {
      v1::Camera* out = resp->add_cameras();
      *out = to_proto(c.rig->cameras()[c.index], *c.rig, c.source);
      out->set_calibration_check(c.calibration_check);
      out->set_calibration_warning(c.calibration_warning);
    }
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::CreateView(grpc::ServerContext* ctx, const v1::CreateViewRequest* req, v1::View* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    if (!req->spec().has_name() || req->spec().name().empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "spec.name is required: every view needs a name");
    }
    *resp = pipeline_.create_view(spec_from_proto(req->spec()));
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::GetView(grpc::ServerContext* ctx, const v1::GetViewRequest* req, v1::View* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    *resp = pipeline_.get_view(req->name());
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::ListViews(grpc::ServerContext* ctx, const v1::ListViewsRequest*,
                                        v1::ListViewsResponse* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  return guarded([&] {
    for (auto& v : pipeline_.list_views()) *resp->add_views() = std::move(v);
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::UpdateView(grpc::ServerContext* ctx, const v1::UpdateViewRequest* req, v1::View* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    *resp = pipeline_.update_view(req->name(), [&](ViewSpec& spec) {
      apply_patch(req->set(), spec);
      apply_delta(req->delta(), spec);
    });
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::DeleteView(grpc::ServerContext* ctx, const v1::DeleteViewRequest* req,
                                         v1::DeleteViewResponse*) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    pipeline_.delete_view(req->name());
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::StreamFrames(grpc::ServerContext* ctx, const v1::StreamFramesRequest* req,
                                           grpc::ServerWriter<v1::Frame>* writer) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    const EncodingKey key = encoding_key(req->encoding(), req->quality(), req->gray(), req->max_bitrate_kbps());
    if (!(req->max_rate_hz() >= 0)) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "max_rate_hz must be >= 0 (0: as fast as frames come)");
    }
    const double rate = req->max_rate_hz() == 0 ? limits_.max_rate_hz : std::min(req->max_rate_hz(), limits_.max_rate_hz);
    // The rate actually served, in the response's initial metadata (and why, when capped).
    std::ostringstream served;
    served << rate;
    ctx->AddInitialMetadata("omniview-max-rate-hz", served.str());
    // The rules of this stream, said to the client up front (docs/API.md, "Streams").
    ctx->AddInitialMetadata("omniview-stream-limits",
                            "delivery=latest-frame-wins; max_rate_hz=" + served.str() +
                                "; max_streams_per_connection=" + std::to_string(limits_.max_streams_per_client) +
                                "; max_streams=" + std::to_string(limits_.max_streams) +
                                "; max_message_bytes=" + std::to_string(limits_.max_message_bytes));
    if (req->max_rate_hz() > limits_.max_rate_hz) {
      std::ostringstream text;
      text << "max_rate_hz " << req->max_rate_hz() << " capped to " << rate << " Hz (the daemon's limits.max_rate_hz)";
      const std::string note = text.str();
      ctx->AddInitialMetadata("omniview-note", note);
      std::cerr << "omniviewd: stream of view '" << req->view() << "' for " << ctx->peer() << ": " << note
                << std::endl;
    }
    StreamSlot slot(*this, ctx->peer());
    if (auto s = slot.acquire(); !s.ok()) return s;
    const auto subscriber = pipeline_.subscribe(req->view(), ctx->peer(), key, rate, req->stale_frames());
    while (true) {
      if (ctx->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client cancelled");
      const auto frame = subscriber->take(kFrontEndPoll);
      if (!frame) continue;  // timed out: check for cancellation and wait again
      if (!*frame) return closed_status(*subscriber);
      // Checked last, against the view's revision now: the view may have changed since the
      // frame was taken (docs/API.md, "Streams").
      if (!subscriber->hand_over(**frame)) continue;
      if (!writer->Write(**frame)) return grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
    }
  });
}

grpc::Status OmniviewService::GetSnapshot(grpc::ServerContext* ctx, const v1::SnapshotRequest* req, v1::Frame* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    if (req->encoding() == v1::H264) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "a snapshot is a still: use JPEG, PNG or RAW (H264 is for StreamFrames)");
    }
    const EncodingKey key = encoding_key(req->encoding(), req->quality(), req->gray());
    constexpr int kMaxSnapshotWaitMs = 60000;
    if (req->timeout_ms() < 0 || req->timeout_ms() > kMaxSnapshotWaitMs) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "timeout_ms must be 0..60000 (0: 5000), got " + std::to_string(req->timeout_ms()));
    }
    const int timeout_ms = req->timeout_ms() > 0 ? req->timeout_ms() : 5000;
    const auto subscriber = pipeline_.subscribe(req->view(), ctx->peer(), key, 0);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (std::chrono::steady_clock::now() < deadline) {
      if (ctx->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client cancelled");
      const auto frame = subscriber->take(kFrontEndPoll);
      if (!frame) continue;
      if (!*frame) return closed_status(*subscriber);
      if (!subscriber->hand_over(**frame)) continue;  // the view changed since it was taken
      *resp = **frame;
      return grpc::Status::OK;
    }
    const auto view = pipeline_.get_view(req->view());
    return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                        "no frame of view '" + req->view() + "' within " + std::to_string(timeout_ms) +
                            " ms: source '" + view.spec().source() +
                            "' is not delivering images (see `omniview status`)");
  });
}

grpc::Status OmniviewService::PixelToRay(grpc::ServerContext* ctx, const v1::PixelToRayRequest* req,
                                         v1::PixelToRayResponse* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    // Pixel centres are at integers, so the image spans [-0.5, W - 0.5]; a click outside it
    // has no ray (the surface would extrapolate one that no camera pixel stands for).
    const auto spec = pipeline_.get_view(req->view()).spec();
    const double u = req->u(), v = req->v();
    if (!(u >= -0.5 && u <= spec.width() - 0.5 && v >= -0.5 && v <= spec.height() - 0.5)) {
      std::ostringstream m;
      m << "pixel (" << u << ", " << v << ") is outside view '" << req->view() << "' (" << spec.width() << "x"
        << spec.height() << ": u in [-0.5, " << spec.width() - 0.5 << "], v in [-0.5, " << spec.height() - 0.5 << "])";
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, m.str());
    }
    const PixelRay ray = pipeline_.pixel_to_ray(req->view(), u, v);
    resp->set_robot_frame(ray.robot_frame);
    *resp->mutable_origin() = to_proto(ray.origin);
    resp->set_valid(ray.valid);
    if (ray.valid) {
      *resp->mutable_direction() = to_proto(ray.direction);
      *resp->mutable_direction_view() = to_proto(ray.direction_view);
    }
    if (ray.surface_point) *resp->mutable_surface_point() = to_proto(*ray.surface_point);
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::PointToPixel(grpc::ServerContext* ctx, const v1::PointToPixelRequest* req,
                                           v1::PointToPixelResponse* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    if (const auto uv = pipeline_.point_to_pixel(req->view(), from_proto(req->point()), req->frame())) {
      resp->set_visible(true);
      resp->set_u(uv->x());
      resp->set_v(uv->y());
    }
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::GetStatus(grpc::ServerContext* ctx, const v1::GetStatusRequest*, v1::Status* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  return guarded([&] {
    *resp = status_message(pipeline_.report(), black_box_ ? black_box_->report() : std::vector<BlackBoxRingReport>{});
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::SaveBlackBox(grpc::ServerContext* ctx, const v1::SaveBlackBoxRequest* req,
                                           v1::SaveBlackBoxResponse* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    if (black_box_ == nullptr) {
      return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                          "this daemon keeps no black box: add `blackbox: {minutes: 5, max_bytes: 2G, folder: blackbox}` "
                          "to its config");
    }
    try {
      for (const SnapshotSummary& s : black_box_->save(req->name(), req->source())) {
        auto* out = resp->add_snapshots();
        out->set_source(s.source);
        out->set_folder(s.folder.string());
        out->set_frame_sets(s.frame_sets);
        out->set_span_s(s.span.count());
        out->set_bytes(s.bytes);
        out->set_note(s.note);
      }
    } catch (const SnapshotError& e) {
      using Kind = SnapshotError::Kind;
      const ErrorKind kind = e.kind() == Kind::kInvalidName     ? ErrorKind::kInvalidArgument
                             : e.kind() == Kind::kExists        ? ErrorKind::kAlreadyExists
                             : e.kind() == Kind::kUnknownSource ? ErrorKind::kNotFound
                             : e.kind() == Kind::kEmpty         ? ErrorKind::kFailedPrecondition
                                                                : ErrorKind::kInternal;
      return grpc_status(grpc_code(kind), e.what());
    }
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::SetJointPositions(grpc::ServerContext* ctx, const v1::SetJointPositionsRequest* req,
                                                v1::JointPositions* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    const JointMap positions(req->positions().begin(), req->positions().end());
    *resp = to_proto(pipeline_.set_joint_positions(req->source(), positions, req->clear()));
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::GetJointPositions(grpc::ServerContext* ctx, const v1::GetJointPositionsRequest* req,
                                                v1::JointPositions* resp) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    *resp = to_proto(pipeline_.joint_positions(req->source()));
    return grpc::Status::OK;
  });
}

grpc::Status OmniviewService::StreamSourceFrames(grpc::ServerContext* ctx, const v1::StreamSourceFramesRequest* req,
                                                 grpc::ServerWriter<v1::SourceFrame>* writer) {
  OMNIVIEW_AUTHORIZE(ctx);
  OMNIVIEW_CHECK_BOUNDS(req);
  return guarded([&] {
    ctx->AddInitialMetadata("omniview-stream-limits",
                            "delivery=queued; record_queue_frame_sets=" +
                                std::to_string(limits_.record_queue_frame_sets) +
                                "; max_streams_per_connection=" + std::to_string(limits_.max_streams_per_client) +
                                "; max_streams=" + std::to_string(limits_.max_streams));
    StreamSlot slot(*this, ctx->peer());
    if (auto s = slot.acquire(); !s.ok()) return s;
    const std::string source = req->source();
    const auto tap = pipeline_.tap(source);
    std::shared_ptr<const Rig> last_rig;  // held: a new rig never reuses its address unseen
    while (true) {
      if (ctx->IsCancelled()) return grpc::Status(grpc::StatusCode::CANCELLED, "client cancelled");
      const auto next = tap->take(kFrontEndPoll);
      if (!next) continue;
      if (!next->frames) return grpc::Status(grpc::StatusCode::UNAVAILABLE, tap->close_reason());
      const bool new_rig = next->frames->rig != last_rig;
      last_rig = next->frames->rig;
      const v1::SourceFrame out = to_source_frame(*next->frames, next->skipped_before, new_rig);
      if (!writer->Write(out)) return grpc::Status(grpc::StatusCode::CANCELLED, "client went away");
    }
  });
}

}  // namespace omniview
