// Frames on disk: the encoding a file name asks for, and writing the bytes as sent.
#pragma once

#include <string>
#include <vector>

#include "cli/args.h"
#include "omniview/v1/omniview.pb.h"

namespace omniview::cli {

// .jpg/.jpeg -> JPEG, .png -> PNG, .raw -> RAW; anything else (.h264 too: one file is one
// still) throws UsageError.
v1::Encoding encoding_for_path(const std::string& path);
// v1::JPEG -> "jpg", PNG -> "png", RAW -> "raw", H264 -> "h264".
std::string extension_for(v1::Encoding encoding);
// "jpg", "png", "raw", "h264" (or "jpeg", "264") -> the encoding; throws UsageError naming `what`.
v1::Encoding encoding_from_name(const std::string& name, const std::string& what);

// Writes the frame's bytes to `path` (replacing it); throws std::runtime_error naming it.
void write_frame(const std::string& path, const v1::Frame& frame);

// "1024x512 RGB JPEG, 123.4 KB"
std::string describe_frame(const v1::Frame& frame);

// The options `watch` and `stream` share: --encoding, --rate, --gray, --quality, --bitrate.
const std::vector<std::string>& stream_flags();
const std::vector<std::string>& stream_switches();
const char* stream_help();
v1::StreamFramesRequest stream_request(const Args& args, const std::string& view, v1::Encoding fallback);

}  // namespace omniview::cli
