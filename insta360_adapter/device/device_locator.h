// Finds the /dev/video node the config names: a path, a USB vendor:product, a USB serial
// number or a name, looked up in sysfs (so the right camera opens whatever order USB
// enumerated the devices in, and again after it was unplugged and came back).
#pragma once

#include <string>
#include <vector>

namespace omniview::insta360 {

struct VideoNode {
  std::string dev_path;  // /dev/video2
  std::string name;      // the driver's name for it (a UVC camera's USB product string)
  std::string vendor, product, serial;  // USB ids (4 hex digits each) and serial, if USB
  int index = 0;         // 0: the capture node of a UVC camera (1: its metadata node)
};

// Every video node sysfs lists (under `sysfs_root`/class/video4linux), by node number.
std::vector<VideoNode> list_video_nodes(const std::string& sysfs_root = "/sys");

// `spec` is "/dev/video2", "usb:2e1a:1000" or "2e1a:1000" (vendor:product, hex),
// "serial:ABC123" or "name:Insta360" (a case-insensitive part of the name). The first
// capture node (index 0) matching; empty when none is plugged in. Throws
// std::invalid_argument for a spec of none of these forms.
std::string find_video_node(const std::string& spec, const std::string& sysfs_root = "/sys");

// What is plugged in, one line per capture node, for error messages.
std::string describe_video_nodes(const std::string& sysfs_root = "/sys");

}  // namespace omniview::insta360
