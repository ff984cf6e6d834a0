// Every field a client sends is bounded: each one out of range (and a huge name) is
// refused with INVALID_ARGUMENT naming the field and quoting at most a short prefix, and
// the daemon goes on serving everyone else.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "daemon_process.h"

namespace omniview::testing {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void expect_refused(const grpc::Status& s, const std::string& field, const std::string& what) {
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << what << ": " << s.error_message();
  EXPECT_NE(s.error_message().find(field), std::string::npos) << what << ": " << s.error_message();
  EXPECT_LT(s.error_message().size(), 600u) << what << ": quotes too much";
}

v1::ViewSpec base(v1::ViewType type = v1::PERSPECTIVE) {
  v1::ViewSpec spec;
  spec.set_name("probe");
  spec.set_type(type);
  spec.set_width(64);
  spec.set_height(32);
  return spec;
}

struct Case {
  std::string field;  // named in the refusal
  std::function<void(v1::ViewSpec&)> set;
};

const std::vector<Case>& out_of_range() {
  static const std::vector<Case> cases = {
      {"name", [](v1::ViewSpec& s) { s.set_name(std::string(65, 'a')); }},
      {"name", [](v1::ViewSpec& s) { s.set_name("two words"); }},
      {"width", [](v1::ViewSpec& s) { s.set_width(0); }},
      {"width", [](v1::ViewSpec& s) { s.set_width(20000); }},
      {"height", [](v1::ViewSpec& s) { s.set_height(-5); }},
      {"source", [](v1::ViewSpec& s) { s.set_source(std::string(300, 's')); }},
      {"frame", [](v1::ViewSpec& s) { s.set_frame(std::string(200, 'f')); }},
      {"frame", [](v1::ViewSpec& s) { s.set_frame("base\nlink"); }},
      {"position.x", [](v1::ViewSpec& s) { s.mutable_position()->set_x(1e6); }},
      {"position.z", [](v1::ViewSpec& s) { s.mutable_position()->set_z(kNaN); }},
      {"yaw_deg", [](v1::ViewSpec& s) { s.set_yaw_deg(1e300); }},
      {"yaw_deg", [](v1::ViewSpec& s) { s.set_yaw_deg(kInf); }},
      {"pitch_deg", [](v1::ViewSpec& s) { s.set_pitch_deg(91); }},
      {"roll_deg", [](v1::ViewSpec& s) { s.set_roll_deg(-400); }},
      {"hfov_deg", [](v1::ViewSpec& s) { s.set_hfov_deg(1e-306); }},
      {"hfov_deg", [](v1::ViewSpec& s) { s.set_hfov_deg(180); }},
      {"distance", [](v1::ViewSpec& s) { s.set_distance(0); }},
      {"distance", [](v1::ViewSpec& s) { s.set_distance(1e9); }},
      {"feather_px", [](v1::ViewSpec& s) { s.set_feather_px(1e12); }},
      {"feather_px", [](v1::ViewSpec& s) { s.set_feather_px(kNaN); }},
      {"overlay_opacity", [](v1::ViewSpec& s) { s.set_overlay_opacity(2); }},
  };
  return cases;
}

// Surface parameters of the other view types.
const std::vector<std::pair<v1::ViewType, Case>>& out_of_range_by_type() {
  static const std::vector<std::pair<v1::ViewType, Case>> cases = {
      {v1::BIRDSEYE, {"height", [](v1::ViewSpec& s) { s.set_height_m(1e7); }}},
      {v1::BIRDSEYE, {"ground_z", [](v1::ViewSpec& s) { s.set_ground_z(-1e7); }}},
      {v1::CYLINDRICAL, {"radius", [](v1::ViewSpec& s) { s.set_radius(1e9); }}},
      {v1::CYLINDRICAL, {"vfov_deg", [](v1::ViewSpec& s) { s.set_vfov_deg(0); }}},
      {v1::CYLINDRICAL, {"azimuth_span_deg", [](v1::ViewSpec& s) { s.set_azimuth_span_deg(1e-9); }}},
      {v1::EQUIRECTANGULAR, {"lat_min_deg", [](v1::ViewSpec& s) { s.set_lat_min_deg(-100); }}},
      {v1::FISHEYE, {"fov_deg", [](v1::ViewSpec& s) { s.set_fov_deg(1e-9); }}},
      {v1::FISHEYE, {"radius", [](v1::ViewSpec& s) { s.set_radius(-1); }}},
  };
  return cases;
}

class RequestBounds : public ::testing::Test {
 protected:
  RequestBounds()
      : daemon_(dir_, example_config(20, "views:\n  - {name: front, type: perspective, width: 128, height: 64}\n")),
        stub_(make_stub(daemon_.address())) {}

  // Another client's stream, open through all of it.
  void expect_others_still_served(grpc::ClientReader<v1::Frame>& watcher) {
    v1::Frame f;
    for (int i = 0; i < 3; ++i) ASSERT_TRUE(watcher.Read(&f)) << "the watcher's stream ended";
    EXPECT_EQ(f.view(), "front");
    v1::ListViewsResponse list;
    ASSERT_TRUE(make_stub(daemon_.address())->ListViews(make_context().get(), {}, &list).ok());
    ASSERT_EQ(list.views_size(), 1);
    EXPECT_EQ(list.views(0).spec().name(), "front");
    EXPECT_EQ(list.views(0).revision(), 1u) << "a refused update changed the view";
  }

  TempDir dir_;
  DaemonProcess daemon_;
  std::unique_ptr<v1::Omniview::Stub> stub_;
};

TEST_F(RequestBounds, CreateAndUpdateRefuseEveryFieldOutOfRange) {
  auto watcher_stub = make_stub(daemon_.address());
  auto watcher_ctx = make_context("", std::chrono::seconds(120));
  v1::StreamFramesRequest watch;
  watch.set_view("front");
  auto watcher = watcher_stub->StreamFrames(watcher_ctx.get(), watch);
  v1::View view;
  for (const auto& c : out_of_range()) {
    v1::CreateViewRequest create;
    *create.mutable_spec() = base();
    c.set(*create.mutable_spec());
    expect_refused(stub_->CreateView(make_context().get(), create, &view), c.field, "CreateView " + c.field);
    v1::UpdateViewRequest update;
    update.set_name("front");
    c.set(*update.mutable_set());
    update.mutable_set()->clear_type();
    if (c.field != "name") update.mutable_set()->clear_name();
    update.mutable_set()->clear_width();
    update.mutable_set()->clear_height();
    if (c.field == "width" || c.field == "height") c.set(*update.mutable_set());
    expect_refused(stub_->UpdateView(make_context().get(), update, &view), c.field, "UpdateView " + c.field);
  }
  for (const auto& [type, c] : out_of_range_by_type()) {
    v1::CreateViewRequest create;
    *create.mutable_spec() = base(type);
    c.set(*create.mutable_spec());
    expect_refused(stub_->CreateView(make_context().get(), create, &view), c.field, "CreateView " + c.field);
  }
  expect_others_still_served(*watcher);
}

TEST_F(RequestBounds, ZoomAndStepsThatWouldLeaveTheBoundsAreRefused) {
  v1::View view;
  const auto delta = [&](std::function<void(v1::ViewDelta&)> set) {
    v1::UpdateViewRequest update;
    update.set_name("front");
    set(*update.mutable_delta());
    return stub_->UpdateView(make_context().get(), update, &view);
  };
  // Zoom 1e308 once gave an hfov of 1e-306 deg while CreateView refused 0.
  expect_refused(delta([](v1::ViewDelta& d) { d.set_zoom(1e308); }), "hfov_deg", "zoom 1e308");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_zoom(kNaN); }), "zoom", "zoom NaN");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_zoom(-2); }), "zoom", "zoom -2");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_yaw_deg(kInf); }), "yaw_deg", "yaw step inf");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_roll_deg(kNaN); }), "roll_deg", "roll step NaN");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_yaw_deg(1e308); }), "delta.yaw_deg", "yaw step 1e308");
  expect_refused(delta([](v1::ViewDelta& d) { d.set_pitch_deg(-361); }), "delta.pitch_deg", "pitch step -361");
  // A joystick's steps stay within bounds however long it is held: pan and roll wrap.
  for (int i = 0; i < 40; ++i) {
    ASSERT_TRUE(delta([](v1::ViewDelta& d) {
                  d.set_yaw_deg(25);
                  d.set_roll_deg(-25);
                }).ok());
  }
  EXPECT_LE(std::abs(view.spec().yaw_deg()), 180);
  EXPECT_LE(std::abs(view.spec().roll_deg()), 180);
}

TEST_F(RequestBounds, AHugeNameIsRefusedShortlyAndBreaksNobodysListing) {
  const std::string huge(3 << 20, 'n');     // 3 MiB: once it broke ListViews for every client
  const std::string long_name(20000, 'x');  // once overflowed the status metadata
  v1::View view;
  v1::CreateViewRequest create;
  *create.mutable_spec() = base();
  create.mutable_spec()->set_name(huge);
  expect_refused(stub_->CreateView(make_context().get(), create, &view), "spec.name", "3 MiB name");
  v1::GetViewRequest get;
  get.set_name(long_name);
  const auto s = stub_->GetView(make_context().get(), get, &view);
  expect_refused(s, "name", "GetView 20000");
  EXPECT_NE(s.error_message().find("20000 characters"), std::string::npos) << s.error_message();
  v1::DeleteViewRequest del;
  del.set_name(long_name);
  v1::DeleteViewResponse deleted;
  expect_refused(stub_->DeleteView(make_context().get(), del, &deleted), "name", "DeleteView");
  v1::SnapshotRequest snap;
  snap.set_view(long_name);
  v1::Frame frame;
  expect_refused(stub_->GetSnapshot(make_context().get(), snap, &frame), "view", "GetSnapshot");
  snap.set_view("front");
  snap.set_timeout_ms(1 << 30);
  expect_refused(stub_->GetSnapshot(make_context().get(), snap, &frame), "timeout_ms", "GetSnapshot timeout");
  v1::StreamFramesRequest stream;
  stream.set_view(long_name);
  auto ctx = make_context();
  auto reader = stub_->StreamFrames(ctx.get(), stream);
  while (reader->Read(&frame)) {
  }
  expect_refused(reader->Finish(), "view", "StreamFrames");
  v1::PointToPixelRequest point;
  point.set_view("front");
  point.mutable_point()->set_x(kNaN);
  v1::PointToPixelResponse pixel;
  expect_refused(stub_->PointToPixel(make_context().get(), point, &pixel), "point.x", "PointToPixel NaN");
  v1::ListViewsResponse list;
  ASSERT_TRUE(stub_->ListViews(make_context().get(), {}, &list).ok());
  EXPECT_EQ(list.views_size(), 1);
}

TEST_F(RequestBounds, JointPositionsAreBoundedBeforeAnyModelIsAsked) {
  v1::JointPositions joints;
  const auto set = [&](std::function<void(v1::SetJointPositionsRequest&)> fill) {
    v1::SetJointPositionsRequest req;
    fill(req);
    return stub_->SetJointPositions(make_context().get(), req, &joints);
  };
  expect_refused(set([](auto& r) { (*r.mutable_positions())["elbow"] = kInf; }), "positions[elbow]", "inf");
  expect_refused(set([](auto& r) { (*r.mutable_positions())[std::string(5000, 'j')] = 1; }), "positions", "long joint");
  expect_refused(set([](auto& r) {
                   for (int i = 0; i < 1000; ++i) (*r.mutable_positions())[std::to_string(i) + "_joint"] = 0;
                 }),
                 "positions", "1000 joints");
  expect_refused(set([](auto& r) { r.set_source(std::string(1000, 's')); }), "source", "long source");
  // Within bounds, the daemon answers as before: this source has no robot model.
  EXPECT_EQ(set([](auto& r) { (*r.mutable_positions())["elbow"] = 0.5; }).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
}

}  // namespace
}  // namespace omniview::testing
