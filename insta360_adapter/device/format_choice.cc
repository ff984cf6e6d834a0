#include "insta360_adapter/device/format_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace omniview::insta360 {

std::string fourcc_text(uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = char((code >> (8 * i)) & 0xFF);
    s += (c >= 32 && c < 127) ? c : '?';
  }
  return s;
}

std::string describe(const FormatOption& o) {
  std::string s = fourcc_text(o.pixel_format) + " " + std::to_string(o.width) + "x" + std::to_string(o.height);
  if (!o.fps.empty()) {
    s += " @ ";
    for (size_t i = 0; i < o.fps.size(); ++i) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%g", o.fps[i]);
      if (i) s += '/';
      s += buf;
    }
    s += " fps";
  }
  return s;
}

std::string describe(const std::vector<FormatOption>& options) {
  if (options.empty()) return "(nothing)";
  std::string s;
  for (const auto& o : options) s += (s.empty() ? "" : ", ") + describe(o);  // one line: status shows one
  return s;
}

CaptureFormat choose_format(const std::vector<FormatOption>& offers, const FormatRequest& request,
                            const std::string& device) {
  const auto rank = [&](uint32_t f) {
    const auto it = std::find(request.pixel_formats.begin(), request.pixel_formats.end(), f);
    return it == request.pixel_formats.end() ? -1 : int(it - request.pixel_formats.begin());
  };
  const FormatOption* best = nullptr;
  for (const auto& o : offers) {
    if (rank(o.pixel_format) < 0 || o.width <= 0 || o.height <= 0) continue;
    if (request.width > 0 && (o.width != request.width || o.height != request.height)) continue;
    if (request.aspect > 0 && std::abs(double(o.width) / o.height - request.aspect) > 0.01) continue;
    if (request.fps > 0 && !o.fps.empty() &&
        std::none_of(o.fps.begin(), o.fps.end(), [&](double f) { return std::abs(f - request.fps) < 0.01; })) {
      continue;
    }
    const auto area = [](const FormatOption* x) { return int64_t(x->width) * x->height; };
    if (!best || area(&o) > area(best) || (area(&o) == area(best) && rank(o.pixel_format) < rank(best->pixel_format))) {
      best = &o;
    }
  }
  if (!best) {
    std::string wanted;
    for (uint32_t f : request.pixel_formats) {
      if (!wanted.empty()) wanted += " or ";
      wanted += fourcc_text(f);
    }
    if (request.width > 0) wanted += " " + std::to_string(request.width) + "x" + std::to_string(request.height);
    if (request.aspect > 0) wanted += " (width:height " + std::to_string(request.aspect).substr(0, 4) + ":1)";
    if (request.fps > 0) wanted += " @ " + std::to_string(request.fps).substr(0, 5) + " fps";
    throw DeviceError(DeviceFault::kNoFormat,
                      device + " offers no " + wanted + "; it offers: " + describe(offers));
  }
  CaptureFormat chosen{best->pixel_format, best->width, best->height, 0, 0};
  chosen.fps = request.fps > 0 ? request.fps
                               : (best->fps.empty() ? 0 : *std::max_element(best->fps.begin(), best->fps.end()));
  return chosen;
}

}  // namespace omniview::insta360
