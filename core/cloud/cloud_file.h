// Point cloud files: PLY (ascii, binary either byte order) and PCD v0.7 (ascii, binary).
//
// Readers take x, y, z (any scalar type) and the fields PointCloud knows by their usual
// names (red/green/blue or packed rgb, intensity, time, ring, flags, camera); others are
// skipped, as are other PLY elements (a mesh's faces). Malformed data throws
// CloudFormatError naming the file and the element, field or line. Writers record the
// frame and stamp in comments ("omniview frame", "omniview stamp_ns"), which the readers
// restore; colours go out as uchar red/green/blue (PLY) or packed rgb (PCD), which MeshLab,
// CloudCompare and PCL show.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

#include "core/cloud/point_cloud.h"

namespace omniview {

enum class CloudEncoding { kBinary, kAscii };

// No limit on a cloud's points (the readers' default).
inline constexpr size_t kAnyNumberOfPoints = std::numeric_limits<size_t>::max();

// `name` is what errors call the data (a file name). A header that declares more than
// `max_points` points is refused before its body is read (CloudFormatError naming the limit).
PointCloud parse_ply(std::string_view data, const std::string& name, size_t max_points = kAnyNumberOfPoints);
std::string format_ply(const PointCloud& cloud, CloudEncoding encoding = CloudEncoding::kBinary);

PointCloud parse_pcd(std::string_view data, const std::string& name, size_t max_points = kAnyNumberOfPoints);
std::string format_pcd(const PointCloud& cloud, CloudEncoding encoding = CloudEncoding::kBinary);

// By content (PLY starts with "ply", PCD with a comment or a header keyword), so a file's
// extension does not matter. Throws CloudFormatError naming the file.
PointCloud load_cloud(const std::string& path, size_t max_points = kAnyNumberOfPoints);
// By extension: .ply or .pcd (anything else is an error naming the file).
void save_cloud(const PointCloud& cloud, const std::string& path, CloudEncoding encoding = CloudEncoding::kBinary);

}  // namespace omniview
