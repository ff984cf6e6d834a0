#include "core/geometry/frame_graph.h"

#include <stdexcept>

namespace omniview {

void FrameGraph::set_parent(const std::string& child, const std::string& parent,
                            const Pose& T_parent_child) {
  if (child.empty() || parent.empty()) throw std::invalid_argument("frame names must not be empty");
  if (child == parent) throw std::invalid_argument("frame '" + child + "' cannot be its own parent");
  // Walk up from the new parent: meeting `child` would close a loop.
  for (std::string f = parent;;) {
    if (f == child) {
      throw std::invalid_argument("linking '" + child + "' under '" + parent +
                                  "' would make a cycle in the frame graph");
    }
    auto it = links_.find(f);
    if (it == links_.end()) break;
    f = it->second.parent;
  }
  links_[child] = Link{parent, T_parent_child};
  roots_.erase(child);
  if (!links_.count(parent)) roots_[parent] = 0;
}

bool FrameGraph::has_frame(const std::string& name) const {
  return links_.count(name) || roots_.count(name);
}

std::optional<std::string> FrameGraph::parent_of(const std::string& name) const {
  const auto it = links_.find(name);
  if (it == links_.end()) return std::nullopt;
  return it->second.parent;
}

std::vector<std::string> FrameGraph::frames() const {
  std::vector<std::string> out;
  for (const auto& [name, _] : roots_) out.push_back(name);
  for (const auto& [name, _] : links_) out.push_back(name);
  return out;
}

Pose FrameGraph::pose_in_root(const std::string& frame, std::string* root) const {
  Pose T = Pose::Identity();
  std::string f = frame;
  for (auto it = links_.find(f); it != links_.end(); it = links_.find(f)) {
    T = it->second.T_parent_child * T;
    f = it->second.parent;
  }
  *root = f;
  return T;
}

std::optional<Pose> FrameGraph::try_lookup(const std::string& a, const std::string& b) const {
  if (!has_frame(a) || !has_frame(b)) return std::nullopt;
  std::string root_a, root_b;
  const Pose T_root_a = pose_in_root(a, &root_a);
  const Pose T_root_b = pose_in_root(b, &root_b);
  if (root_a != root_b) return std::nullopt;
  return T_root_a.inverse() * T_root_b;
}

Pose FrameGraph::lookup(const std::string& a, const std::string& b) const {
  if (auto T = try_lookup(a, b)) return *T;
  for (const auto* f : {&a, &b}) {
    if (!has_frame(*f)) throw std::out_of_range("unknown frame '" + *f + "'");
  }
  throw std::out_of_range("frames '" + a + "' and '" + b + "' are not connected");
}

}  // namespace omniview
