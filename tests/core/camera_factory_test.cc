// make_camera_model / describe: kalibr names and parameter orders in, clear errors out.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "camera_cases.h"
#include "core/camera/camera_model.h"
#include "test_support.h"

namespace omniview {
namespace {

const std::string kWhat = "rig.yaml: camera 'cam7'";

void expect_rejected(const ModelSpec& spec, std::initializer_list<std::string> needles) {
  testing::expect_throw_containing<std::invalid_argument>([&] { make_camera_model(spec, kWhat); }, needles,
                                                          spec.camera_model + "+" + spec.distortion_model);
  // Every message names the camera it is about.
  testing::expect_throw_containing<std::invalid_argument>([&] { make_camera_model(spec, kWhat); }, {kWhat});
}

TEST(CameraFactory, BuildsEveryModelWithKalibrParameterOrder) {
  Eigen::Vector2d uv;
  // pinhole [fu fv pu pv]: the axis lands on (pu, pv), x scales with fu.
  const CameraModel pin = make_camera_model({"pinhole", "none", {400, 300, 320, 240}, {}}, kWhat);
  ASSERT_TRUE(project(pin, {0.1, 0.2, 1}, uv));
  EXPECT_LT((uv - Eigen::Vector2d(360, 300)).norm(), 1e-12);
  EXPECT_TRUE(std::holds_alternative<PinholeRadtan>(pin));
  // An empty distortion_model means none (kalibr omits it for ds and eucm).
  EXPECT_TRUE(std::holds_alternative<PinholeRadtan>(make_camera_model({"pinhole", "", {1, 1, 0, 0}, {}}, kWhat)));
  const auto radtan4 =
      make_camera_model({"pinhole", "radtan", {400, 400, 320, 240}, {-0.1, 0.01, 0.001, 0.002}}, kWhat);
  EXPECT_EQ(std::get<PinholeRadtan>(radtan4).distortion().p2, 0.002);
  EXPECT_EQ(std::get<PinholeRadtan>(radtan4).distortion().k3, 0);
  const auto radtan5 =
      make_camera_model({"pinhole", "radtan", {400, 400, 320, 240}, {-0.1, 0.01, 0.001, 0.002, -0.003}}, kWhat);
  EXPECT_EQ(std::get<PinholeRadtan>(radtan5).distortion().k3, -0.003);
  const auto kb =
      make_camera_model({"pinhole", "equidistant", {258, 259, 511.5, 512.5}, {0.02, -0.004, 0.0005, -0.0001}}, kWhat);
  EXPECT_EQ(std::get<Equidistant>(kb).k(), Eigen::Vector4d(0.02, -0.004, 0.0005, -0.0001));
  EXPECT_EQ(std::get<Fov>(make_camera_model({"pinhole", "fov", {1, 1, 0, 0}, {0.9}}, kWhat)).w(), 0.9);
  // omni [xi fu fv pu pv], ds [xi alpha fu fv pu pv], eucm [alpha beta fu fv pu pv].
  const auto omni =
      std::get<OmniRadtan>(make_camera_model({"omni", "radtan", {0.9, 700, 701, 320, 240}, {-0.2, 0.05, 0, 0}}, kWhat));
  EXPECT_EQ(omni.xi(), 0.9);
  EXPECT_EQ(omni.fv(), 701);
  const auto ds = std::get<DoubleSphere>(make_camera_model({"ds", "none", {-0.2, 0.6, 350, 351, 320, 240}, {}}, kWhat));
  EXPECT_EQ(ds.xi(), -0.2);
  EXPECT_EQ(ds.alpha(), 0.6);
  EXPECT_EQ(ds.pv(), 240);
  const auto eucm = std::get<Eucm>(make_camera_model({"eucm", "none", {0.6, 1.1, 350, 351, 320, 240}, {}}, kWhat));
  EXPECT_EQ(eucm.alpha(), 0.6);
  EXPECT_EQ(eucm.beta(), 1.1);
  EXPECT_EQ(eucm.fu(), 350);
}

TEST(CameraFactory, DescribeRoundTripsThroughTheFactory) {
  for (const auto& c : testing::camera_cases()) {
    const ModelSpec spec = describe(c.model);
    const CameraModel again = make_camera_model(spec, c.name);
    EXPECT_EQ(again.index(), c.model.index()) << c.name;
    const ModelSpec spec2 = describe(again);
    EXPECT_EQ(spec.camera_model, spec2.camera_model) << c.name;
    EXPECT_EQ(spec.distortion_model, spec2.distortion_model) << c.name;
    EXPECT_EQ(spec.intrinsics, spec2.intrinsics) << c.name;
    EXPECT_EQ(spec.distortion, spec2.distortion) << c.name;
    // And the rebuilt model images exactly like the original.
    for (double theta = 0; theta < std::min(c.max_theta, 1.5); theta += 0.1) {
      Eigen::Vector2d a, b;
      ASSERT_TRUE(project(c.model, testing::ray_at(theta, 0.4), a));
      ASSERT_TRUE(project(again, testing::ray_at(theta, 0.4), b));
      EXPECT_EQ(a, b) << c.name;
    }
  }
  // 4 coefficients stay 4 (k3 = 0 is not written), 5 stay 5.
  EXPECT_EQ(describe(make_camera_model({"pinhole", "radtan", {1, 1, 0, 0}, {0.1, 0, 0, 0}}, "")).distortion.size(), 4u);
  EXPECT_EQ(describe(make_camera_model({"omni", "radtan", {1, 1, 1, 0, 0}, {0.1, 0, 0, 0, 0.2}}, "")).distortion.size(),
            5u);
}

TEST(CameraFactory, EverySupportedCombinationIsAccepted) {
  for (const auto& info : supported_models()) {
    ModelSpec spec{info.camera_model, info.distortion_model, {}, {}};
    spec.intrinsics = info.camera_model == "pinhole" ? std::vector<double>{300, 300, 320, 240}
                      : info.camera_model == "omni"  ? std::vector<double>{0.9, 300, 300, 320, 240}
                      : info.camera_model == "ds"    ? std::vector<double>{-0.2, 0.6, 300, 300, 320, 240}
                                                     : std::vector<double>{0.6, 1.1, 300, 300, 320, 240};
    if (info.distortion_model == "radtan") spec.distortion = {-0.1, 0.01, 0, 0};
    if (info.distortion_model == "equidistant") spec.distortion = {0.01, 0, 0, 0};
    if (info.distortion_model == "fov") spec.distortion = {0.9};
    EXPECT_NO_THROW(make_camera_model(spec, kWhat)) << info.camera_model << "+" << info.distortion_model;
  }
}

TEST(CameraFactory, UnknownModelsAndCombinations) {
  expect_rejected({"kb4", "none", {1, 1, 0, 0}, {}}, {"unknown camera_model 'kb4'", "pinhole+radtan"});
  expect_rejected({"ds", "radtan", {0, 0.5, 1, 1, 0, 0}, {0, 0, 0, 0}},
                  {"camera_model ds", "distortion_model none", "'radtan'"});
  expect_rejected({"eucm", "equidistant", {0.5, 1, 1, 1, 0, 0}, {0, 0, 0, 0}},
                  {"camera_model eucm", "distortion_model"});
  expect_rejected({"omni", "equidistant", {0.9, 1, 1, 0, 0}, {0, 0, 0, 0}}, {"distortion_model 'equidistant'", "omni"});
  expect_rejected({"pinhole", "kb", {1, 1, 0, 0}, {}}, {"distortion_model 'kb' is not supported"});
  expect_rejected({"ds", "none", {0, 0.5, 1, 1, 0, 0}, {0.1}}, {"distortion_coeffs"});
}

TEST(CameraFactory, WrongParameterCountsNameTheField) {
  expect_rejected({"pinhole", "none", {1, 1, 0}, {}}, {"intrinsics needs 4 values", "got 3"});
  expect_rejected({"pinhole", "radtan", {1, 1, 0, 0}, {0, 0, 0}}, {"distortion_coeffs needs 4 or 5 values", "got 3"});
  expect_rejected({"pinhole", "radtan", {1, 1, 0, 0}, {0, 0, 0, 0, 0, 0}}, {"distortion_coeffs needs 4 or 5 values"});
  expect_rejected({"pinhole", "equidistant", {1, 1, 0, 0}, {0, 0, 0, 0, 0}}, {"distortion_coeffs needs 4 values"});
  expect_rejected({"pinhole", "fov", {1, 1, 0, 0}, {}}, {"distortion_coeffs needs 1 value ["});
  expect_rejected({"omni", "none", {0.9, 1, 1, 0}, {}}, {"intrinsics needs 5 values"});
  expect_rejected({"ds", "none", {0.9, 0.5, 1, 1, 0}, {}}, {"intrinsics needs 6 values"});
  expect_rejected({"eucm", "none", {0.5, 1, 1, 1, 0, 0, 0}, {}}, {"intrinsics needs 6 values", "got 7"});
  expect_rejected({"pinhole", "none", {1, 1, 0, 0}, {0.1, 0, 0, 0}}, {"distortion_model none", "distortion_coeffs"});
}

TEST(CameraFactory, NonFiniteAndImpossibleValuesNameTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  expect_rejected({"pinhole", "none", {nan, 1, 0, 0}, {}}, {"intrinsics", "non-finite"});
  expect_rejected({"pinhole", "none", {1, 1, inf, 0}, {}}, {"intrinsics", "non-finite"});
  expect_rejected({"pinhole", "radtan", {1, 1, 0, 0}, {0, nan, 0, 0}}, {"distortion_coeffs", "non-finite"});
  expect_rejected({"pinhole", "equidistant", {1, 1, 0, 0}, {0, 0, -inf, 0}}, {"distortion_coeffs", "non-finite"});
  expect_rejected({"ds", "none", {nan, 0.5, 1, 1, 0, 0}, {}}, {"intrinsics", "non-finite"});
  // Focal lengths <= 0, in every model's own position.
  expect_rejected({"pinhole", "none", {0, 1, 0, 0}, {}}, {"intrinsics", "focal lengths"});
  expect_rejected({"pinhole", "equidistant", {1, -1, 0, 0}, {0, 0, 0, 0}}, {"intrinsics", "focal lengths"});
  expect_rejected({"omni", "none", {0.9, -300, 300, 0, 0}, {}}, {"intrinsics", "focal lengths"});
  expect_rejected({"ds", "none", {0.1, 0.5, 300, 0, 0, 0}, {}}, {"intrinsics", "focal lengths"});
  expect_rejected({"eucm", "none", {0.5, 1, -1, 300, 0, 0}, {}}, {"intrinsics", "focal lengths"});
  // Model parameters outside their domain.
  expect_rejected({"omni", "none", {-0.1, 300, 300, 0, 0}, {}}, {"intrinsics", "xi"});
  expect_rejected({"ds", "none", {0.1, 1.5, 300, 300, 0, 0}, {}}, {"intrinsics", "alpha"});
  expect_rejected({"ds", "none", {-1.0, 0.5, 300, 300, 0, 0}, {}}, {"intrinsics", "xi"});
  expect_rejected({"eucm", "none", {1.5, 1, 1, 1, 0, 0}, {}}, {"intrinsics", "alpha must be in [0, 1]"});
  expect_rejected({"eucm", "none", {0.5, 0, 1, 1, 0, 0}, {}}, {"intrinsics", "beta"});
  expect_rejected({"pinhole", "fov", {1, 1, 0, 0}, {0}}, {"distortion_coeffs", "fov w"});
  expect_rejected({"pinhole", "fov", {1, 1, 0, 0}, {3.2}}, {"distortion_coeffs", "fov w"});
}

}  // namespace
}  // namespace omniview
