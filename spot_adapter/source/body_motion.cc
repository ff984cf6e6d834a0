#include "spot_adapter/source/body_motion.h"

#include <map>

namespace omniview::spot {
namespace {

// T_root_frame, walking parent links up to the snapshot's root (bounded: a malformed
// snapshot with a cycle gives nullopt, not a hang).
std::optional<std::pair<std::string, Pose>> to_root(const std::map<std::string, const FrameEdge*>& parent_of,
                                                    std::string frame) {
  Pose T = Pose::Identity();
  for (size_t depth = 0; depth <= parent_of.size(); ++depth) {
    const auto it = parent_of.find(frame);
    if (it == parent_of.end()) return std::make_pair(frame, T);
    T = it->second->T_parent_child * T;
    frame = it->second->parent;
  }
  return std::nullopt;
}

}  // namespace

std::optional<Pose> pose_in_snapshot(const std::vector<FrameEdge>& edges, const std::string& fixed,
                                     const std::string& body) {
  std::map<std::string, const FrameEdge*> parent_of;
  for (const auto& e : edges) parent_of[e.child] = &e;
  if (!parent_of.count(fixed) && !parent_of.count(body)) return std::nullopt;  // neither is in it
  const auto a = to_root(parent_of, fixed), b = to_root(parent_of, body);
  if (!a || !b || a->first != b->first) return std::nullopt;
  return a->second.inverse() * b->second;
}

}  // namespace omniview::spot
