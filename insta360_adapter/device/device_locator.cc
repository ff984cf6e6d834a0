#include "insta360_adapter/device/device_locator.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace omniview::insta360 {
namespace {

namespace fs = std::filesystem;

std::string read_line(const fs::path& p) {
  std::string s;
  std::ifstream in(p);
  std::getline(in, s);
  return s;
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

int node_number(const std::string& name) {  // "video12" -> 12
  try {
    return std::stoi(name.substr(5));
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace

std::vector<VideoNode> list_video_nodes(const std::string& sysfs_root) {
  std::vector<std::pair<int, VideoNode>> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(sysfs_root) / "class" / "video4linux", ec)) {
    const std::string node = entry.path().filename().string();
    if (node.rfind("video", 0) != 0) continue;
    VideoNode v;
    v.dev_path = "/dev/" + node;
    v.name = read_line(entry.path() / "name");
    const std::string index = read_line(entry.path() / "index");
    v.index = index.empty() ? 0 : std::atoi(index.c_str());
    // The node's device is a USB interface; the USB device (idVendor, idProduct, serial)
    // is the first folder above it that has them.
    std::error_code link_ec;
    fs::path dir = fs::canonical(entry.path() / "device", link_ec);
    for (int up = 0; !link_ec && up < 4 && !dir.empty() && dir != dir.root_path(); ++up, dir = dir.parent_path()) {
      if (fs::exists(dir / "idVendor")) {
        v.vendor = lower(read_line(dir / "idVendor"));
        v.product = lower(read_line(dir / "idProduct"));
        v.serial = read_line(dir / "serial");
        break;
      }
    }
    found.emplace_back(node_number(node), std::move(v));
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<VideoNode> out;
  for (auto& [_, v] : found) out.push_back(std::move(v));
  return out;
}

std::string find_video_node(const std::string& spec, const std::string& sysfs_root) {
  if (!spec.empty() && spec[0] == '/') return spec;
  static const std::regex usb_id("(?:usb:)?([0-9a-fA-F]{4}):([0-9a-fA-F]{4})");
  std::smatch m;
  std::function<bool(const VideoNode&)> match;
  if (std::regex_match(spec, m, usb_id)) {
    const std::string vendor = lower(m[1]), product = lower(m[2]);
    match = [=](const VideoNode& v) { return v.vendor == vendor && v.product == product; };
  } else if (spec.rfind("serial:", 0) == 0 && spec.size() > 7) {
    const std::string serial = spec.substr(7);
    match = [=](const VideoNode& v) { return !v.serial.empty() && v.serial == serial; };
  } else if (spec.rfind("name:", 0) == 0 && spec.size() > 5) {
    const std::string part = lower(spec.substr(5));
    match = [=](const VideoNode& v) { return lower(v.name).find(part) != std::string::npos; };
  } else {
    throw std::invalid_argument("'" + spec +
                                "' is no device: give /dev/videoN, vendor:product (hex, e.g. 2e1a:1000), "
                                "serial:NUMBER or name:PART");
  }
  for (const auto& v : list_video_nodes(sysfs_root)) {
    if (v.index == 0 && match(v)) return v.dev_path;
  }
  return "";
}

std::string describe_video_nodes(const std::string& sysfs_root) {
  std::string out;
  for (const auto& v : list_video_nodes(sysfs_root)) {
    if (v.index != 0) continue;
    out += (out.empty() ? "" : "; ") + v.dev_path + " '" + v.name + "'";
    if (!v.vendor.empty()) out += " usb " + v.vendor + ":" + v.product;
    if (!v.serial.empty()) out += " serial " + v.serial;
  }
  return out.empty() ? "no video devices are plugged in" : "plugged in: " + out;
}

}  // namespace omniview::insta360
