#include "cli/client/frame_files.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "cli/args.h"
#include "cli/client/command_support.h"

namespace omniview::cli {

v1::Encoding encoding_from_name(const std::string& name, const std::string& what) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "jpg" || n == "jpeg") return v1::JPEG;
  if (n == "png") return v1::PNG;
  if (n == "raw") return v1::RAW;
  if (n == "h264" || n == "264") return v1::H264;
  throw UsageError(what + ": '" + name + "' is not an encoding (jpg, png, raw or h264)");
}

v1::Encoding encoding_for_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext.empty()) throw UsageError("'" + path + "': name the file .png, .jpg or .raw to choose the encoding");
  // One file is one still image: a video stream is `omniview stream --encoding h264`.
  v1::Encoding encoding = v1::ENCODING_UNSPECIFIED;
  try {
    encoding = encoding_from_name(ext.substr(1), "'" + path + "'");
  } catch (const UsageError&) {
  }
  if (encoding == v1::ENCODING_UNSPECIFIED || encoding == v1::H264) {
    throw UsageError("'" + path + "': '" + ext.substr(1) + "' is not an image encoding (jpg, png or raw)");
  }
  return encoding;
}

std::string extension_for(v1::Encoding encoding) {
  switch (encoding) {
    case v1::PNG:
      return "png";
    case v1::RAW:
      return "raw";
    case v1::H264:
      return "h264";
    default:
      return "jpg";
  }
}

void write_frame(const std::string& path, const v1::Frame& frame) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(frame.data().data(), static_cast<std::streamsize>(frame.data().size()));
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
}

std::string describe_frame(const v1::Frame& frame) {
  const std::string colour = frame.channels() == 1 ? " gray" : frame.channels() == 3 ? " RGB" : "";
  const std::string encoding = frame.encoding() == v1::PNG    ? "PNG"
                               : frame.encoding() == v1::RAW  ? "RAW"
                               : frame.encoding() == v1::H264 ? (frame.key_frame() ? "H.264 key frame" : "H.264")
                                                              : "JPEG";
  return std::to_string(frame.width()) + "x" + std::to_string(frame.height()) + colour + " " + encoding + ", " +
         fixed(frame.data().size() / 1024.0, 1) + " KB";
}

}  // namespace omniview::cli

namespace omniview::cli {

const std::vector<std::string>& stream_flags() {
  static const std::vector<std::string> flags{"encoding", "rate", "quality", "bitrate"};
  return flags;
}

const std::vector<std::string>& stream_switches() {
  static const std::vector<std::string> switches{"gray", "grey"};
  return switches;
}

const char* stream_help() {
  return R"(  --encoding E       jpg, png, raw or h264 (frames as the daemon sends them)
  --rate HZ          at most this many frames per second (default: as the source delivers)
  --gray             one channel even when some camera is colour
  --quality Q        1..100: JPEG quality (default 85); for h264 the constant rate factor
                     CRF = 51 - Q/2 (default 50: CRF 26)
  --bitrate KBPS     h264: a ceiling in kbit/s (50..100000) over the quality (default none)
)";
}

v1::StreamFramesRequest stream_request(const Args& args, const std::string& view, v1::Encoding fallback) {
  v1::StreamFramesRequest request;
  request.set_view(view);
  request.set_encoding(args.has("encoding") ? encoding_from_name(args.get("encoding"), "--encoding") : fallback);
  if (args.has("rate")) request.set_max_rate_hz(parse_positive(args.get("rate"), "--rate"));
  if (args.has("quality")) {
    const int quality = parse_count(args.get("quality"), "--quality");
    if (quality > 100) throw UsageError("--quality: expected 1..100");
    request.set_quality(quality);
  }
  if (args.has("bitrate")) {
    if (request.encoding() != v1::H264) throw UsageError("--bitrate: only with --encoding h264");
    const int kbps = parse_count(args.get("bitrate"), "--bitrate");
    if (kbps < 50 || kbps > 100000) throw UsageError("--bitrate: expected 50..100000 kbit/s");
    request.set_max_bitrate_kbps(kbps);
  }
  request.set_gray(args.has("gray") || args.has("grey"));
  request.set_stale_frames(true);  // every command says when the picture is not live (StaleNotice)
  return request;
}

}  // namespace omniview::cli
