// Views through the real daemon: create, read, update, delete; frames of every encoding,
// with the sizes and camera descriptions asked for; clicks and overlays; bad requests.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "core/io/image_codec.h"
#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/rig/rig.h"
#include "daemon_process.h"

namespace omniview::testing {
namespace {

v1::ViewSpec perspective(const std::string& name, int w, int h, double hfov) {
  v1::ViewSpec s;
  s.set_name(name);
  s.set_type(v1::PERSPECTIVE);
  s.set_width(w);
  s.set_height(h);
  s.set_hfov_deg(hfov);
  return s;
}

class ViewsApi : public ::testing::Test {
 protected:
  ViewsApi() : daemon_(dir_, example_config(30)), stub_(make_stub(daemon_.address())) {}

  grpc::Status create(const v1::ViewSpec& spec, v1::View* out = nullptr) {
    v1::CreateViewRequest req;
    *req.mutable_spec() = spec;
    v1::View view;
    const auto s = stub_->CreateView(make_context().get(), req, &view);
    if (out) *out = view;
    return s;
  }

  // The first `n` frames of `view` in `encoding`.
  std::vector<v1::Frame> frames(const std::string& view, v1::Encoding encoding, int n) {
    v1::StreamFramesRequest req;
    req.set_view(view);
    req.set_encoding(encoding);
    auto ctx = make_context();
    auto reader = stub_->StreamFrames(ctx.get(), req);
    std::vector<v1::Frame> out;
    v1::Frame f;
    while (static_cast<int>(out.size()) < n && reader->Read(&f)) out.push_back(f);
    ctx->TryCancel();
    reader->Finish();
    return out;
  }

  TempDir dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

TEST_F(ViewsApi, CreateGetListUpdateDelete) {
  v1::View created;
  ASSERT_TRUE(create(perspective("front", 320, 160, 90), &created).ok());
  EXPECT_EQ(created.revision(), 1u);
  EXPECT_EQ(created.spec().width(), 320);
  EXPECT_EQ(created.spec().source(), "examples");  // the default source filled in
  ASSERT_EQ(created.intrinsics_size(), 4);
  EXPECT_NEAR(created.intrinsics(0), 160.0, 1e-9);  // f = (W/2) / tan(hfov/2)
  EXPECT_NEAR(created.intrinsics(2), 159.5, 1e-9);  // principal point at the centre
  EXPECT_NE(created.yaml().find("type: perspective"), std::string::npos);
  EXPECT_TRUE(created.spec().gain_compensation());  // on by default, as in the YAML schema

  v1::View got;
  v1::GetViewRequest get;
  get.set_name("front");
  ASSERT_TRUE(stub_->GetView(make_context().get(), get, &got).ok());
  EXPECT_EQ(got.SerializeAsString(), created.SerializeAsString());

  EXPECT_EQ(create(perspective("front", 64, 32, 60)).error_code(), grpc::StatusCode::ALREADY_EXISTS);

  v1::UpdateViewRequest update;
  update.set_name("front");
  update.mutable_set()->set_hfov_deg(60);
  update.mutable_set()->set_gain_compensation(false);
  update.mutable_delta()->set_yaw_deg(15);
  v1::View updated;
  ASSERT_TRUE(stub_->UpdateView(make_context().get(), update, &updated).ok());
  EXPECT_EQ(updated.revision(), 2u);
  EXPECT_FALSE(updated.spec().gain_compensation());
  EXPECT_NE(updated.yaml().find("gain_compensation: false"), std::string::npos);
  EXPECT_DOUBLE_EQ(updated.spec().hfov_deg(), 60);
  EXPECT_DOUBLE_EQ(updated.spec().yaw_deg(), 15);
  EXPECT_EQ(updated.spec().width(), 320);  // untouched fields stay

  v1::ListViewsResponse list;
  ASSERT_TRUE(stub_->ListViews(make_context().get(), {}, &list).ok());
  ASSERT_EQ(list.views_size(), 1);

  v1::DeleteViewRequest del;
  del.set_name("front");
  v1::DeleteViewResponse deleted;
  ASSERT_TRUE(stub_->DeleteView(make_context().get(), del, &deleted).ok());
  const auto again = stub_->DeleteView(make_context().get(), del, &deleted);
  EXPECT_EQ(again.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(again.error_message().find("front"), std::string::npos);
  EXPECT_EQ(stub_->GetView(make_context().get(), get, &got).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST_F(ViewsApi, FramesInEveryEncodingHaveTheRequestedSizeAndCamera) {
  ASSERT_TRUE(create(perspective("front", 320, 160, 100)).ok());
  v1::ViewSpec pano;
  pano.set_name("pano");
  pano.set_type(v1::CYLINDRICAL);
  pano.set_width(400);
  pano.set_height(200);
  ASSERT_TRUE(create(pano).ok());

  for (const auto encoding : {v1::JPEG, v1::PNG, v1::RAW}) {
    SCOPED_TRACE(v1::Encoding_Name(encoding));
    const auto got = frames("pano", encoding, 2);
    ASSERT_EQ(got.size(), 2u);
    const v1::Frame& f = got.back();
    EXPECT_EQ(f.view(), "pano");
    EXPECT_EQ(f.encoding(), encoding);
    EXPECT_EQ(f.width(), 400);
    EXPECT_EQ(f.height(), 200);
    EXPECT_GT(f.sequence(), got.front().sequence());
    EXPECT_EQ(f.camera().spec().type(), v1::CYLINDRICAL);
    EXPECT_EQ(f.camera().revision(), 1u);
    EXPECT_GT(f.coverage(), 0.99);  // two 210 deg lenses see all around
    EXPECT_GE(f.latency_ms(), 0);
    EXPECT_GT(f.capture_time().seconds(), 1'600'000'000);
    if (encoding == v1::RAW) {
      EXPECT_EQ(f.data().size(), size_t(400 * 200 * f.channels()));
    } else {
      const cv::Mat img = decode_image(f.data());
      ASSERT_FALSE(img.empty());
      EXPECT_EQ(img.cols, 400);
      EXPECT_EQ(img.rows, 200);
      EXPECT_EQ(img.channels(), f.channels());
      EXPECT_GT(cv::mean(img)[0], 20);  // a picture, not black
    }
  }
}

// What the daemon sends is exactly what the core renders offline from the same images; and
// an update shows at once, as docs/API.md ("Streams") promises: once UpdateView has
// returned, the daemon hands no frame of the old revision to the transport. What it had
// handed over before may still arrive, and a client skips that by its revision.
TEST_F(ViewsApi, PngFramesEqualTheOfflineRenderAndFollowUpdatesImmediately) {
  // The paper's nearest rule, whose daemon and offline renders agree bit for bit (a blend
  // may differ by a grey level of rounding between the two apply paths).
  auto nearest = perspective("ptz", 256, 128, 90);
  nearest.set_fusion(v1::NEAREST_CENTRE);
  ASSERT_TRUE(create(nearest).ok());
  v1::StreamFramesRequest req;
  req.set_view("ptz");
  req.set_encoding(v1::PNG);
  auto ctx = make_context();
  auto reader = stub_->StreamFrames(ctx.get(), req);
  v1::Frame f;
  ASSERT_TRUE(reader->Read(&f));
  ASSERT_EQ(f.camera().revision(), 1u);

  v1::UpdateViewRequest update;
  update.set_name("ptz");
  update.mutable_delta()->set_yaw_deg(40);
  update.mutable_delta()->set_pitch_deg(10);
  update.mutable_delta()->set_zoom(2);
  v1::View updated;
  ASSERT_TRUE(stub_->UpdateView(make_context().get(), update, &updated).ok());
  EXPECT_NEAR(updated.spec().hfov_deg(), 2 * std::atan(0.5) * 180 / M_PI, 1e-9);  // zoom 2 halves tan(hfov/2)
  ASSERT_EQ(updated.revision(), 2u);

  // The frames handed to the transport so far, counted after UpdateView returned: every
  // frame of the old revision is among them (a bound, since a few of the new one may be
  // counted too). The daemon counts a frame as sent when it hands it over.
  v1::Status status;
  ASSERT_TRUE(stub_->GetStatus(make_context().get(), {}, &status).ok());
  uint64_t handed_over = 0;
  for (const auto& c : status.clients()) {
    if (c.view() == "ptz") handed_over = c.frames_sent();
  }
  ASSERT_GE(handed_over, 1u);

  // Skipped by revision, as `omniview show` does: only frames handed over before that count.
  uint64_t old_frames = 1;  // the one read before the update
  while (true) {
    ASSERT_TRUE(reader->Read(&f));
    if (f.camera().revision() == updated.revision()) break;
    ASSERT_EQ(f.camera().revision(), 1u);
    ASSERT_LT(old_frames++, handed_over) << "a frame of the old view was handed over after UpdateView returned";
  }
  EXPECT_DOUBLE_EQ(f.camera().spec().yaw_deg(), 40);
  v1::Frame next;  // and the stream never goes back
  ASSERT_TRUE(reader->Read(&next));
  EXPECT_EQ(next.camera().revision(), updated.revision());
  ctx->TryCancel();
  reader->Finish();

  const Rig rig = load_rig(example_dir() + "/rig.yaml");
  ViewSpec spec = default_view_spec(ViewType::kPerspective);
  spec.width = 256;
  spec.height = 128;
  spec.hfov_deg = updated.spec().hfov_deg();
  spec.yaw_deg = 40;
  spec.pitch_deg = 10;
  spec.fusion = Fusion::kNearestCentre;
  const auto view = View::create(spec);
  std::vector<cv::Mat> images;
  for (const auto& cam : rig.cameras()) {
    images.push_back(read_image(example_dir() + "/" + cam.name + ".jpg", ImageColour::kBgr));
  }
  cv::Mat expected;
  apply_map(build_map(rig, *view), images, expected, 3);
  const cv::Mat got = decode_image(f.data());
  ASSERT_EQ(got.size(), expected.size());
  EXPECT_EQ(cv::norm(got, expected, cv::NORM_INF), 0);
}

TEST_F(ViewsApi, PixelToRayAndBack) {
  ASSERT_TRUE(create(perspective("front", 321, 161, 90)).ok());
  v1::PixelToRayRequest click;
  click.set_view("front");
  click.set_u(160);
  click.set_v(80);
  v1::PixelToRayResponse ray;
  ASSERT_TRUE(stub_->PixelToRay(make_context().get(), click, &ray).ok());
  ASSERT_TRUE(ray.valid());
  EXPECT_EQ(ray.robot_frame(), "base_link");
  EXPECT_NEAR(ray.direction().x(), 1, 1e-9);  // the centre pixel looks straight ahead
  EXPECT_NEAR(ray.direction().y(), 0, 1e-9);

  click.set_u(40.25);
  click.set_v(120.5);
  ASSERT_TRUE(stub_->PixelToRay(make_context().get(), click, &ray).ok());
  v1::PointToPixelRequest back;
  back.set_view("front");
  *back.mutable_point() = ray.surface_point();
  v1::PointToPixelResponse px;
  ASSERT_TRUE(stub_->PointToPixel(make_context().get(), back, &px).ok());
  ASSERT_TRUE(px.visible());
  EXPECT_NEAR(px.u(), 40.25, 1e-6);
  EXPECT_NEAR(px.v(), 120.5, 1e-6);

  back.mutable_point()->set_x(-5);  // behind the view
  back.mutable_point()->set_y(0);
  ASSERT_TRUE(stub_->PointToPixel(make_context().get(), back, &px).ok());
  EXPECT_FALSE(px.visible());

  // The image spans [-0.5, W - 0.5]: its corner has a ray, a pixel far outside none.
  click.set_u(-0.5);
  click.set_v(160.5);
  ASSERT_TRUE(stub_->PixelToRay(make_context().get(), click, &ray).ok());
  EXPECT_TRUE(ray.valid());
  click.set_u(5000);
  const auto outside = stub_->PixelToRay(make_context().get(), click, &ray);
  EXPECT_EQ(outside.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(outside.error_message().find("is outside view 'front' (321x161"), std::string::npos)
      << outside.error_message();
}

TEST_F(ViewsApi, CamerasCarryTheirCalibration) {
  v1::ListCamerasResponse cams;
  ASSERT_TRUE(stub_->ListCameras(make_context().get(), {}, &cams).ok());
  ASSERT_EQ(cams.cameras_size(), 2);
  const Rig rig = load_rig(example_dir() + "/rig.yaml");
  for (int i = 0; i < 2; ++i) {
    const auto& c = cams.cameras(i);
    EXPECT_EQ(c.name(), rig.cameras()[i].name);
    EXPECT_EQ(c.source(), "examples");
    EXPECT_EQ(c.width(), rig.cameras()[i].width);
    EXPECT_EQ(c.camera_model(), "pinhole");
    EXPECT_EQ(c.distortion_model(), "equidistant");
    EXPECT_EQ(c.intrinsics_size(), 4);
    EXPECT_EQ(c.distortion_coeffs_size(), 4);
    const Pose expected = rig.camera_pose("base_link", i);
    EXPECT_NEAR(c.pose().translation().x(), expected.translation().x(), 1e-12);
    EXPECT_NEAR(std::abs(c.pose().qw()), std::abs(Eigen::Quaterniond(expected.rotation()).w()), 1e-12);
  }
  v1::ListCamerasRequest unknown;
  unknown.set_source("nope");
  const auto s = stub_->ListCameras(make_context().get(), unknown, &cams);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(s.error_message().find("examples"), std::string::npos);  // says what exists
}

TEST_F(ViewsApi, BadRequestsGetClearErrors) {
  struct Case {
    v1::ViewSpec spec;
    grpc::StatusCode code;
    std::string says;
  };
  std::vector<Case> cases;
  cases.push_back({perspective("wide", 320, 160, 180), grpc::StatusCode::INVALID_ARGUMENT, "hfov"});
  cases.push_back({perspective("empty", 0, 160, 90), grpc::StatusCode::INVALID_ARGUMENT, "width"});
  cases.push_back({perspective("huge", 20000, 20000, 90), grpc::StatusCode::INVALID_ARGUMENT, "max_view_pixels"});
  cases.push_back({perspective("", 320, 160, 90), grpc::StatusCode::INVALID_ARGUMENT, "name"});
  auto untyped = perspective("untyped", 320, 160, 90);
  untyped.clear_type();
  cases.push_back({untyped, grpc::StatusCode::INVALID_ARGUMENT, "type"});
  auto elsewhere = perspective("elsewhere", 320, 160, 90);
  elsewhere.set_source("lidar");
  cases.push_back({elsewhere, grpc::StatusCode::NOT_FOUND, "lidar"});
  auto unframed = perspective("unframed", 320, 160, 90);
  unframed.set_frame("odom");
  cases.push_back({unframed, grpc::StatusCode::INVALID_ARGUMENT, "odom"});
  cases.push_back({perspective("two words", 320, 160, 90), grpc::StatusCode::INVALID_ARGUMENT, "no spaces"});
  auto upside_down = perspective("flipped", 320, 160, 90);
  upside_down.set_pitch_deg(120);
  cases.push_back({upside_down, grpc::StatusCode::INVALID_ARGUMENT, "pitch_deg (tilt) must be in [-90, 90]"});
  // A key of another view type: named with the type, not silently ignored.
  auto fisheye_key = perspective("mixed", 320, 160, 90);
  fisheye_key.set_fov_deg(200);
  cases.push_back({fisheye_key, grpc::StatusCode::INVALID_ARGUMENT,
                   "view 'mixed': fov_deg does not apply to perspective views (their keys: hfov_deg, distance, ground_z, ground)"});
  for (const auto& c : cases) {
    SCOPED_TRACE(c.spec.ShortDebugString());
    const auto s = create(c.spec);
    EXPECT_EQ(s.error_code(), c.code) << s.error_message();
    EXPECT_NE(s.error_message().find(c.says), std::string::npos) << s.error_message();
  }

  ASSERT_TRUE(create(perspective("front", 64, 32, 90)).ok());
  v1::UpdateViewRequest zoom_pano;
  zoom_pano.set_name("front");
  zoom_pano.mutable_delta()->set_zoom(-1);
  v1::View v;
  EXPECT_EQ(stub_->UpdateView(make_context().get(), zoom_pano, &v).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  // Partial updates: a key of another type is refused; the full spec GetView returns,
  // sent back unchanged, is fine (its other keys keep their values).
  v1::UpdateViewRequest radius;
  radius.set_name("front");
  radius.mutable_set()->set_radius(7);
  auto s = stub_->UpdateView(make_context().get(), radius, &v);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("radius does not apply to perspective views"), std::string::npos)
      << s.error_message();
  v1::UpdateViewRequest round_trip;
  round_trip.set_name("front");
  ASSERT_TRUE(stub_->GetView(make_context().get(), [] {
    v1::GetViewRequest r;
    r.set_name("front");
    return r;
  }(), &v).ok());
  *round_trip.mutable_set() = v.spec();
  round_trip.mutable_set()->set_yaw_deg(10);
  s = stub_->UpdateView(make_context().get(), round_trip, &v);
  EXPECT_TRUE(s.ok()) << s.error_message();
  // A tilt step beyond straight down stops there.
  v1::UpdateViewRequest tilt;
  tilt.set_name("front");
  tilt.mutable_delta()->set_pitch_deg(200);
  ASSERT_TRUE(stub_->UpdateView(make_context().get(), tilt, &v).ok());
  EXPECT_EQ(v.spec().pitch_deg(), 90);

  v1::SnapshotRequest snap;
  snap.set_view("front");
  snap.set_quality(101);
  v1::Frame f;
  s = stub_->GetSnapshot(make_context().get(), snap, &f);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("quality"), std::string::npos);

  snap.set_view("nope");
  snap.set_quality(0);
  EXPECT_EQ(stub_->GetSnapshot(make_context().get(), snap, &f).error_code(), grpc::StatusCode::NOT_FOUND);
  snap.set_view("front");
  ASSERT_TRUE(stub_->GetSnapshot(make_context().get(), snap, &f).ok());
  EXPECT_EQ(f.width(), 64);
}

TEST_F(ViewsApi, StatusReportsSourcesViewsAndClients) {
  ASSERT_TRUE(create(perspective("front", 128, 64, 90)).ok());
  ASSERT_TRUE(create(perspective("unwatched", 128, 64, 90)).ok());
  v1::StreamFramesRequest req;
  req.set_view("front");
  auto ctx = make_context();
  auto reader = stub_->StreamFrames(ctx.get(), req);
  v1::Frame f;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(reader->Read(&f));

  v1::Status st;
  ASSERT_TRUE(stub_->GetStatus(make_context().get(), {}, &st).ok());
  ASSERT_EQ(st.sources_size(), 1);
  EXPECT_EQ(st.sources(0).name(), "examples");
  EXPECT_EQ(st.sources(0).type(), "images");
  EXPECT_TRUE(st.sources(0).connected());
  EXPECT_NEAR(st.sources(0).rate_hz(), 30, 10);
  EXPECT_LT(st.sources(0).last_frame_age_s(), 1 * test_time_scale());  // 30 Hz: a sanitizer may stretch it
  ASSERT_EQ(st.views_size(), 2);
  for (const auto& v : st.views()) {
    if (v.name() == "front") {
      EXPECT_EQ(v.subscribers(), 1u);
      EXPECT_GE(v.frames(), 9u);  // the 10th may be counted just after it was sent
      EXPECT_EQ(v.map_rebuilds(), 1u);
    } else {
      EXPECT_EQ(v.subscribers(), 0u);
      EXPECT_EQ(v.frames(), 0u);  // nobody watches it: it costs nothing
    }
  }
  ASSERT_EQ(st.clients_size(), 1);
  EXPECT_EQ(st.clients(0).view(), "front");
  EXPECT_GE(st.clients(0).frames_sent(), 10u);  // counted when handed over, before it is read
  ctx->TryCancel();
  reader->Finish();
}

}  // namespace
}  // namespace omniview::testing
