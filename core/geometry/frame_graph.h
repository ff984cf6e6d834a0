// Named coordinate frames joined by rigid transforms (a forest of parent links).
//
// Static for now: rigs and configs add frames once. Adapters that receive live
// transforms (Spot's frame tree) replace edges with set_parent(); lookups then see the
// new pose.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/pose.h"

namespace omniview {

class FrameGraph {
 public:
  // Adds or replaces `child`'s link: T_parent_child. Throws if that would make a cycle.
  void set_parent(const std::string& child, const std::string& parent, const Pose& T_parent_child);

  bool has_frame(const std::string& name) const;
  // The frame `name` hangs from; nullopt for a root or an unknown frame.
  std::optional<std::string> parent_of(const std::string& name) const;
  std::vector<std::string> frames() const;

  // T_a_b: the pose of frame b in frame a. Throws std::out_of_range naming both frames
  // when they are not connected.
  Pose lookup(const std::string& a, const std::string& b) const;
  std::optional<Pose> try_lookup(const std::string& a, const std::string& b) const;

 private:
  struct Link {
    std::string parent;
    Pose T_parent_child;
  };
  // Pose of `frame` in its tree's root, and that root's name.
  Pose pose_in_root(const std::string& frame, std::string* root) const;

  std::map<std::string, Link> links_;  // child -> parent link
  std::map<std::string, int> roots_;   // frames known only as parents
};

}  // namespace omniview
