#include "core/robot/render/gl_projection.h"

namespace omniview::robot {

Eigen::Matrix4d gl_projection(const PinholeCamera& c, double near, double far) {
  // x_ndc = 2 (u + 0.5) / W - 1 with u = fx x/z + cx; clip w = z. Likewise for y and v.
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  P(0, 0) = 2.0 * c.fx / c.width;
  P(0, 2) = 2.0 * (c.cx + 0.5) / c.width - 1.0;
  P(1, 1) = 2.0 * c.fy / c.height;
  P(1, 2) = 2.0 * (c.cy + 0.5) / c.height - 1.0;
  P(2, 2) = (far + near) / (far - near);
  P(2, 3) = -2.0 * far * near / (far - near);
  P(3, 2) = 1.0;
  return P;
}

}  // namespace omniview::robot
