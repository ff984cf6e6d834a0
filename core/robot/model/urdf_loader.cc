#include "core/robot/model/urdf_loader.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "core/robot/model/mesh_loader.h"
#include "core/robot/model/primitives.h"

namespace omniview::robot {
namespace fs = std::filesystem;

namespace {

const Rgba8 kDefaultGrey = rgba8(0.6f, 0.6f, 0.6f);

// urdfdom reports why it rejects a file only through console_bridge; collect its errors
// while parsing (console_bridge's handler is process-wide, hence the lock).
class ErrorCollector : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors += (errors.empty() ? "" : "; ") + text;
  }
  std::string errors;
};

urdf::ModelInterfaceSharedPtr parse(const std::string& xml, std::string& reason) {
  static std::mutex console_mutex;
  std::lock_guard lock(console_mutex);
  ErrorCollector collector;
  console_bridge::useOutputHandler(&collector);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {  // urdfdom throws on some malformed numbers
    collector.errors += (collector.errors.empty() ? "" : "; ") + std::string(e.what());
  }
  console_bridge::restorePreviousOutputHandler();
  reason = collector.errors;
  return model;
}

// urdfdom reads "nan", "inf" and "1e300" as numbers; a robot drawn from them would vanish
// or fill the view (and overflow the renderer's floats), so they are refused where they
// are written. A million (metres, or a mimic's factor) is far beyond any robot.
void check_finite(std::initializer_list<double> values, const std::string& where) {
  for (double v : values) {
    if (!(std::abs(v) <= 1e6)) throw std::runtime_error(where + ": numbers must be finite and within +-1e6");
  }
}

Pose to_pose(const urdf::Pose& p, const std::string& where) {
  check_finite({p.position.x, p.position.y, p.position.z, p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w},
               where + " origin");
  Pose out = Pose::Identity();
  out.translation() = Vec3(p.position.x, p.position.y, p.position.z);
  out.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  return out;
}

// The URDF's own colour for a visual, if it gives one (a texture-only material does not).
bool urdf_colour(const urdf::Visual& v, Rgba8& colour) {
  if (!v.material) return false;
  const urdf::Color& c = v.material->color;
  const bool default_colour = c.r == 0 && c.g == 0 && c.b == 0 && c.a == 1;
  if (!v.material->texture_filename.empty() && default_colour) return false;
  colour = rgba8(c.r, c.g, c.b, c.a);
  return true;
}

class Builder {
 public:
  Builder(const fs::path& urdf_dir, const MeshSearchPath& search, const std::string& what)
      : urdf_dir_(urdf_dir), search_(search), what_(what) {}

  TriangleMesh geometry(const urdf::Geometry& g, const std::string& link) {
    switch (g.type) {
      case urdf::Geometry::BOX: {
        const auto& d = static_cast<const urdf::Box&>(g).dim;
        check_size({d.x, d.y, d.z}, link, "box size");
        return make_box(Eigen::Vector3f(float(d.x), float(d.y), float(d.z)));
      }
      case urdf::Geometry::CYLINDER: {
        const auto& c = static_cast<const urdf::Cylinder&>(g);
        check_size({c.radius, c.length}, link, "cylinder radius and length");
        return make_cylinder(float(c.radius), float(c.length));
      }
      case urdf::Geometry::SPHERE:
        check_size({static_cast<const urdf::Sphere&>(g).radius}, link, "sphere radius");
        return make_sphere(float(static_cast<const urdf::Sphere&>(g).radius));
      case urdf::Geometry::MESH:
        return mesh(static_cast<const urdf::Mesh&>(g), link);
    }
    throw std::runtime_error(what_ + ": link '" + link + "' has a visual of unknown geometry type");
  }

 private:
  // Sizes in metres: positive, and at most a kilometre (anything larger is a typo, and
  // would not survive the conversion to float the renderer needs).
  void check_size(std::initializer_list<double> values, const std::string& link, const std::string& what) const {
    for (double v : values) {
      if (!(v > 0 && v <= 1000)) {
        throw std::runtime_error(what_ + ": link '" + link + "': " + what + " must be in (0, 1000] m");
      }
    }
  }

  TriangleMesh mesh(const urdf::Mesh& m, const std::string& link) {
    const Eigen::Vector3f scale(float(m.scale.x), float(m.scale.y), float(m.scale.z));
    if (!scale.allFinite() || scale.cwiseAbs().minCoeff() == 0) {
      throw std::runtime_error(what_ + ": link '" + link + "': mesh '" + m.filename + "' has a zero or invalid scale");
    }
    fs::path path;
    try {
      path = search_.resolve(m.filename, urdf_dir_);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(what_ + ": link '" + link + "': " + e.what());
    }
    std::ostringstream key;
    key << path.string() << '|' << scale.transpose();
    auto it = cache_.find(key.str());
    if (it == cache_.end()) it = cache_.emplace(key.str(), load_mesh_file(path, scale, kDefaultGrey)).first;
    return it->second;
  }

  fs::path urdf_dir_;
  const MeshSearchPath& search_;
  std::string what_;
  std::map<std::string, TriangleMesh> cache_;  // links often share a mesh file
};

void add_visuals(const urdf::Link& link, int index, Builder& builder, std::vector<Visual>& out,
                 const std::string& what) {
  for (const auto& v : link.visual_array) {
    if (!v || !v->geometry) continue;
    TriangleMesh mesh = builder.geometry(*v->geometry, link.name);
    Rgba8 colour;
    if (urdf_colour(*v, colour)) mesh.set_colour(colour);
    const Pose T = to_pose(v->origin, what + ": link '" + link.name + "' visual");
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    for (auto& p : mesh.positions) p = R * p + t;
    for (auto& n : mesh.normals) n = R * n;
    out.push_back({index, std::move(mesh)});
  }
}

Joint make_joint(const urdf::Joint& j, const std::string& what) {
  Joint out;
  out.name = j.name;
  out.T_parent_joint = to_pose(j.parent_to_joint_origin_transform, what + ": joint '" + j.name + "'");
  switch (j.type) {
    case urdf::Joint::REVOLUTE: out.type = JointType::kRevolute; break;
    case urdf::Joint::CONTINUOUS: out.type = JointType::kContinuous; break;
    case urdf::Joint::PRISMATIC: out.type = JointType::kPrismatic; break;
    default: out.type = JointType::kFixed; break;  // fixed, and floating/planar held at origin
  }
  if (out.type != JointType::kFixed) {
    const Vec3 axis(j.axis.x, j.axis.y, j.axis.z);
    check_finite({axis.x(), axis.y(), axis.z()}, what + ": joint '" + j.name + "' axis");
    if (!(axis.norm() > 1e-9)) throw std::runtime_error(what + ": joint '" + j.name + "' has a zero axis");
    out.axis = axis.normalized();
  }
  if ((out.type == JointType::kRevolute || out.type == JointType::kPrismatic) && j.limits &&
      j.limits->upper > j.limits->lower) {  // both 0: no limits given
    out.limited = true;
    out.lower = j.limits->lower;
    out.upper = j.limits->upper;
  }
  return out;
}

RobotModel build(const urdf::ModelInterface& urdf, const fs::path& urdf_dir, const MeshSearchPath& search,
                 const std::string& what) {
  Builder builder(urdf_dir, search, what);
  std::vector<Link> links;
  std::vector<Visual> visuals;
  std::vector<std::string> variables;
  std::map<std::string, std::string> mimics;  // mimic joint -> joint it follows
  // Breadth first from the root, so parents come before their children.
  std::deque<std::pair<urdf::LinkConstSharedPtr, int>> queue{{urdf.getRoot(), -1}};
  while (!queue.empty()) {
    const auto [link, parent] = queue.front();
    queue.pop_front();
    Link out{link->name, parent, {}};
    if (parent >= 0 && link->parent_joint) {
      out.joint = make_joint(*link->parent_joint, what);
      if (link->parent_joint->mimic) {
        mimics[out.joint.name] = link->parent_joint->mimic->joint_name;
        out.joint.multiplier = link->parent_joint->mimic->multiplier;
        out.joint.offset = link->parent_joint->mimic->offset;
        check_finite({out.joint.multiplier, out.joint.offset}, what + ": joint '" + out.joint.name + "' mimic");
      } else if (out.joint.type != JointType::kFixed) {
        out.joint.variable = static_cast<int>(variables.size());
        variables.push_back(out.joint.name);
      }
    }
    const int index = static_cast<int>(links.size());
    links.push_back(std::move(out));
    add_visuals(*link, index, builder, visuals, what);
    for (const auto& child : link->child_links) queue.emplace_back(child, index);
  }
  for (auto& link : links) {
    const auto it = mimics.find(link.joint.name);
    if (it == mimics.end() || link.parent < 0) continue;
    const auto v = std::find(variables.begin(), variables.end(), it->second);
    if (v == variables.end()) {
      throw std::runtime_error(what + ": joint '" + link.joint.name + "' mimics '" + it->second +
                               "', which is not a movable joint that is not itself a mimic");
    }
    link.joint.variable = static_cast<int>(v - variables.begin());
  }
  return RobotModel(urdf.getName(), std::move(links), std::move(visuals), std::move(variables));
}

}  // namespace

RobotModel load_urdf_string(const std::string& xml, const fs::path& urdf_dir, const MeshSearchPath& search_path,
                            const std::string& what) {
  std::string reason;
  const auto urdf = parse(xml, reason);
  // urdfdom drops some elements it cannot read (a <box> with two sizes, a <cylinder>
  // without a length) and only logs why: the robot would be drawn without them. Any error
  // it reports makes the file malformed.
  if (!urdf || !urdf->getRoot() || !reason.empty()) {
    throw std::runtime_error("malformed URDF " + what + (reason.empty() ? "" : ": " + reason));
  }
  return build(*urdf, urdf_dir, search_path, what);
}

RobotModel load_urdf_file(const fs::path& urdf, const MeshSearchPath& search_path) {
  std::ifstream in(urdf, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read URDF " + urdf.string());
  std::stringstream text;
  text << in.rdbuf();
  return load_urdf_string(text.str(), urdf.parent_path(), search_path, urdf.string());
}

}  // namespace omniview::robot
