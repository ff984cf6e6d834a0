#include "core/cloud/cloud_file.h"

#include <fstream>
#include <iterator>

namespace omniview {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == suffix;
}

}  // namespace

PointCloud load_cloud(const std::string& path, size_t max_points) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CloudFormatError(path + ": cannot open the file");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (data.compare(0, 3, "ply") == 0) return parse_ply(data, path, max_points);
  if (data.empty()) throw CloudFormatError(path + ": the file is empty");
  if (data[0] == '#' || data.compare(0, 7, "VERSION") == 0 || data.compare(0, 6, "FIELDS") == 0) return parse_pcd(data, path, max_points);
  throw CloudFormatError(path + ": neither a PLY nor a PCD file");
}

void save_cloud(const PointCloud& cloud, const std::string& path, CloudEncoding encoding) {
  std::string data;
  if (ends_with(path, ".ply")) {
    data = format_ply(cloud, encoding);
  } else if (ends_with(path, ".pcd")) {
    data = format_pcd(cloud, encoding);
  } else {
    throw std::runtime_error(path + ": unknown cloud file type (use .ply or .pcd)");
  }
  std::ofstream out(path, std::ios::binary);
  out.write(data.data(), static_cast<std::streamsize>(data.size()));
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write the file");
}

}  // namespace omniview
