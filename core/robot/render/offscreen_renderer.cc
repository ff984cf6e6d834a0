#include "core/robot/render/offscreen_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "core/robot/render/gl_projection.h"

namespace omniview::robot {
namespace {

std::mutex& osmesa_mutex() {
  static std::mutex m;
  return m;
}

// Depth range that holds every item in front of the camera: bounding spheres in the
// optical frame. False when everything is behind the camera.
bool depth_range(const std::vector<DrawItem>& items, const Pose& T_camera_robot, double& near, double& far) {
  double lo = std::numeric_limits<double>::max(), hi = 0;
  for (const auto& item : items) {
    Eigen::Vector3f centre;
    float radius;
    item.mesh->bounding_sphere(centre, radius);
    const double z = (T_camera_robot * item.T_robot_mesh * centre.cast<double>()).z();
    lo = std::min(lo, z - radius);
    hi = std::max(hi, z + radius);
  }
  if (!(hi > 0)) return false;
  // Near as far forward as possible (depth precision), but never past the nearest geometry.
  far = hi * 1.01;
  near = std::max(lo * 0.99, far * 1e-4);
  return true;
}

void set_up_lighting() {
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();  // the light is given in the optical frame: a headlight
  const GLfloat direction[] = {0, 0, -1, 0};  // towards the camera, i.e. light along +z
  const GLfloat diffuse[] = {0.75f, 0.75f, 0.75f, 1};
  const GLfloat none[] = {0, 0, 0, 1};
  const GLfloat ambient[] = {0.3f, 0.3f, 0.3f, 1};
  glLightfv(GL_LIGHT0, GL_POSITION, direction);
  glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
  glLightfv(GL_LIGHT0, GL_SPECULAR, none);
  glLightfv(GL_LIGHT0, GL_AMBIENT, none);
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  glEnable(GL_LIGHTING);
  glEnable(GL_LIGHT0);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  glEnable(GL_COLOR_MATERIAL);
  glEnable(GL_NORMALIZE);
  glShadeModel(GL_SMOOTH);
  glFrontFace(GL_CW);  // the projection mirrors y (gl_projection.h)
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
}

void draw(const TriangleMesh& mesh, const Eigen::Matrix4d& modelview) {
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(modelview.data());  // Eigen is column-major, as GL expects
  glVertexPointer(3, GL_FLOAT, sizeof(Eigen::Vector3f), mesh.positions.data());
  glNormalPointer(GL_FLOAT, sizeof(Eigen::Vector3f), mesh.normals.data());
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(Rgba8), mesh.colours.data());
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(mesh.positions.size()));
}

}  // namespace

struct OffscreenRenderer::Context {
  OSMesaContext gl = nullptr;
};

OffscreenRenderer::OffscreenRenderer() : context_(std::make_unique<Context>()) {
  std::lock_guard lock(osmesa_mutex());
  context_->gl = OSMesaCreateContextExt(OSMESA_BGRA, 24, 0, 0, nullptr);
  if (!context_->gl) throw std::runtime_error("OSMesa: cannot create an offscreen GL context");
}

OffscreenRenderer::~OffscreenRenderer() {
  std::lock_guard lock(osmesa_mutex());
  OSMesaDestroyContext(context_->gl);
}

cv::Mat OffscreenRenderer::render(const std::vector<DrawItem>& items, const PinholeCamera& camera,
                                  const Pose& T_robot_camera) {
  if (camera.width <= 0 || camera.height <= 0) throw std::invalid_argument("robot renderer: empty image size");
  cv::Mat image(camera.height, camera.width, CV_8UC4, cv::Scalar::all(0));
  const Pose T_camera_robot = T_robot_camera.inverse();
  double near = 0, far = 0;
  if (items.empty() || !depth_range(items, T_camera_robot, near, far)) return image;

  std::lock_guard lock(osmesa_mutex());
  if (!OSMesaMakeCurrent(context_->gl, image.data, GL_UNSIGNED_BYTE, camera.width, camera.height)) {
    throw std::runtime_error("OSMesa: cannot render " + std::to_string(camera.width) + "x" +
                             std::to_string(camera.height) + " (larger than the implementation's maximum?)");
  }
  glViewport(0, 0, camera.width, camera.height);
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glMatrixMode(GL_PROJECTION);
  const Eigen::Matrix4d P = gl_projection(camera, near, far);
  glLoadMatrixd(P.data());
  set_up_lighting();
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  for (const auto& item : items) draw(*item.mesh, (T_camera_robot * item.T_robot_mesh).matrix());
  glFinish();  // OSMesa copies the finished picture into `image`
  OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);  // let another thread's renderer go next
  return image;
}

}  // namespace omniview::robot
