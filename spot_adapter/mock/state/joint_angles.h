// The leg joints' angles the robot state reports (standing by default; the control service
// moves them so a client's robot-model overlay can be checked).
#pragma once

#include <map>
#include <mutex>
#include <string>

namespace omniview::spot_mock {

class JointAngles {
 public:
  JointAngles();  // standing
  std::map<std::string, double> get() const;
  // Sets the given joints (radians); throws std::invalid_argument naming an unknown joint
  // or a non-finite angle, changing nothing.
  std::map<std::string, double> set(const std::map<std::string, double>& positions);

 private:
  mutable std::mutex mutex_;
  std::map<std::string, double> angles_;
};

}  // namespace omniview::spot_mock
