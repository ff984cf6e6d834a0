#include "server/video/h264_encoder.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

extern "C" {
#include <x264.h>
}

namespace omniview::video {

namespace {

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// x264 reports through a callback: errors are kept for the exception that follows, the
// rest (its informational start-up lines) is dropped, so a daemon's log stays readable.
void keep_errors(void* priv, int level, const char* format, va_list args) {
  if (level > X264_LOG_ERROR) return;
  char line[512];
  std::vsnprintf(line, sizeof line, format, args);
  auto& text = *static_cast<std::string*>(priv);
  text = line;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
}

}  // namespace

void check(const H264Settings& s) {
  if (s.width <= 0 || s.height <= 0 || s.width > kMaxSide || s.height > kMaxSide) {
    throw std::invalid_argument("H.264 needs a picture of 2x2 to " + size_text(kMaxSide, kMaxSide) + ", got " +
                                size_text(s.width, s.height));
  }
  if (!(s.fps > 0 && s.fps <= 1000)) throw std::invalid_argument("H.264 frame rate must be in (0, 1000] Hz");
  if (!(s.crf >= 0 && s.crf <= 51)) throw std::invalid_argument("H.264 CRF must be 0..51");
  if (s.max_kbps != 0 && (s.max_kbps < kMinKbps || s.max_kbps > kMaxKbps)) {
    throw std::invalid_argument("H.264 bitrate must be " + std::to_string(kMinKbps) + ".." + std::to_string(kMaxKbps) +
                                " kbit/s (0: no ceiling), got " + std::to_string(s.max_kbps));
  }
  if (s.threads < 1 || s.threads > 16) throw std::invalid_argument("H.264 encoder threads must be 1..16");
}

struct H264Encoder::X264 {
  x264_t* handle = nullptr;
  x264_picture_t picture{};
  std::string error;
  ~X264() {
    if (handle != nullptr) x264_encoder_close(handle);
  }
};

H264Encoder::H264Encoder(const H264Settings& settings) : settings_(settings), x264_(std::make_unique<X264>()) {
  check(settings_);
  // Checked here: x264 would print its own complaint to stderr.
  bool known = false;
  for (int i = 0; x264_preset_names[i] != nullptr; ++i) known = known || settings_.preset == x264_preset_names[i];
  x264_param_t p;
  if (!known || x264_param_default_preset(&p, settings_.preset.c_str(), "zerolatency") < 0) {
    throw std::invalid_argument("unknown x264 preset '" + settings_.preset + "'");
  }
  p.pf_log = keep_errors;
  p.p_log_private = &x264_->error;
  p.i_log_level = X264_LOG_ERROR;
  p.i_width = coded_width();
  p.i_height = coded_height();
  p.i_csp = X264_CSP_I420;
  // Full-range BT.601 (as JPEG): grey pixels are the luma as they are.
  p.vui.b_fullrange = 1;
  p.vui.i_colorprim = 6;  // SMPTE 170M (BT.601 525)
  p.vui.i_transfer = 6;
  p.vui.i_colmatrix = 6;
  // Low latency: what zerolatency sets, said here so that no default can undo it.
  p.i_bframe = 0;
  p.rc.i_lookahead = 0;
  p.i_sync_lookahead = 0;
  p.rc.b_mb_tree = 0;
  p.b_sliced_threads = 1;
  p.i_threads = settings_.threads;
  // Rate control by frame count at `fps`, not by time stamps: x264 holds one frame back to
  // learn each frame's duration from the next one's stamp (b_vfr_input), a frame of latency.
  // set_frame_rate() keeps a ceiling right when frames come at another rate.
  p.b_vfr_input = 0;
  p.i_timebase_num = 1;
  p.i_timebase_den = 1000;
  const int fps_den = 1000;
  p.i_fps_num = static_cast<uint32_t>(std::lround(settings_.fps * fps_den));
  p.i_fps_den = fps_den;
  p.i_keyint_max = X264_KEYINT_MAX_INFINITE;
  // Every IDR carries SPS and PPS, Annex-B start codes: any IDR is a place to start decoding.
  p.b_repeat_headers = 1;
  p.b_annexb = 1;
  p.rc.i_rc_method = X264_RC_CRF;
  p.rc.f_rf_constant = static_cast<float>(settings_.crf);
  if (settings_.max_kbps > 0) {
    p.rc.i_vbv_max_bitrate = settings_.max_kbps;
    p.rc.i_vbv_buffer_size = settings_.max_kbps;  // one second
  }
  // High profile, 4:2:0, 8 bits: what every browser, player and hardware decoder takes.
  if (x264_param_apply_profile(&p, "high") < 0) throw std::runtime_error("x264 refused the High profile");
  x264_->handle = x264_encoder_open(&p);
  if (x264_->handle == nullptr) {
    throw std::runtime_error("cannot start the H.264 encoder (x264) for " + size_text(coded_width(), coded_height()) +
                             (x264_->error.empty() ? "" : ": " + x264_->error));
  }
  x264_picture_init(&x264_->picture);
  frame_rate_ = settings_.fps;
  yuv_.create(coded_height() * 3 / 2, coded_width(), CV_8UC1);
}

H264Encoder::~H264Encoder() = default;

void H264Encoder::set_frame_rate(double fps) {
  if (settings_.max_kbps == 0 || !(fps > 0)) return;
  // The ceiling is a per-frame budget of max_kbps / settings.fps: scaled so that the
  // budget over a second of frames at `fps` is max_kbps again. Only on a real change
  // (15 %): a reconfiguration is cheap, but not free.
  if (std::abs(fps - frame_rate_) < 0.15 * frame_rate_) return;
  x264_param_t p;
  x264_encoder_parameters(x264_->handle, &p);
  const int kbps = static_cast<int>(std::lround(settings_.max_kbps * settings_.fps / fps));
  p.rc.i_vbv_max_bitrate = kbps;
  p.rc.i_vbv_buffer_size = kbps;
  if (x264_encoder_reconfig(x264_->handle, &p) == 0) frame_rate_ = fps;
}

AccessUnit H264Encoder::encode(const cv::Mat& view_image, int64_t pts_ms, bool key_frame) {
  if (view_image.cols != settings_.width || view_image.rows != settings_.height) {
    throw std::invalid_argument("H.264 encoder for " + size_text(settings_.width, settings_.height) + " got a " +
                                size_text(view_image.cols, view_image.rows) + " image");
  }
  if (view_image.type() != CV_8UC1 && view_image.type() != CV_8UC3) {
    throw std::invalid_argument("H.264 encoder takes 8-bit grey or BGR images, got OpenCV type " +
                                std::to_string(view_image.type()));
  }
  const int w = coded_width(), h = coded_height();
  cv::Mat image = view_image;
  if (w != view_image.cols || h != view_image.rows) {
    cv::copyMakeBorder(view_image, padded_, 0, h - view_image.rows, 0, w - view_image.cols, cv::BORDER_REPLICATE);
    image = padded_;
  }
  cv::Mat y(h, w, CV_8UC1, yuv_.data);
  cv::Mat u(h / 2, w / 2, CV_8UC1, yuv_.data + static_cast<size_t>(w) * h);
  cv::Mat v(h / 2, w / 2, CV_8UC1, yuv_.data + static_cast<size_t>(w) * h * 5 / 4);
  if (image.channels() == 1) {
    image.copyTo(y);
    if (!grey_chroma_ready_) {
      u.setTo(128);
      v.setTo(128);
      grey_chroma_ready_ = true;
    }
  } else {
    // Full-range BT.601 (JPEG's YCbCr), chroma averaged over each 2x2 block.
    cv::Mat ycrcb;
    cv::cvtColor(image, ycrcb, cv::COLOR_BGR2YCrCb);
    cv::Mat planes[3];
    cv::split(ycrcb, planes);
    planes[0].copyTo(y);
    cv::resize(planes[2], u, u.size(), 0, 0, cv::INTER_AREA);  // Cb
    cv::resize(planes[1], v, v.size(), 0, 0, cv::INTER_AREA);  // Cr
    grey_chroma_ready_ = false;
  }
  x264_picture_t& in = x264_->picture;
  in.img.i_csp = X264_CSP_I420;
  in.img.i_plane = 3;
  in.img.plane[0] = y.data;
  in.img.plane[1] = u.data;
  in.img.plane[2] = v.data;
  in.img.i_stride[0] = w;
  in.img.i_stride[1] = w / 2;
  in.img.i_stride[2] = w / 2;
  in.i_type = key_frame ? X264_TYPE_IDR : X264_TYPE_AUTO;
  // x264 needs strictly increasing time stamps; a source that repeats one (a stale
  // picture sent again) still gets a frame.
  if (last_pts_ != INT64_MIN && pts_ms <= last_pts_) pts_ms = last_pts_ + 1;
  last_pts_ = pts_ms;
  in.i_pts = pts_ms;

  x264_nal_t* nals = nullptr;
  int nal_count = 0;
  x264_picture_t out;
  x264_picture_init(&out);
  x264_->error.clear();
  const int bytes = x264_encoder_encode(x264_->handle, &nals, &nal_count, &in, &out);
  if (bytes < 0) {
    throw std::runtime_error("H.264 encoding failed" + (x264_->error.empty() ? "" : ": " + x264_->error));
  }
  // Zero latency: the picture just given comes out of this very call.
  if (bytes == 0 || x264_encoder_delayed_frames(x264_->handle) != 0) {
    throw std::logic_error("the H.264 encoder held a frame back (its low-latency settings did not apply)");
  }
  AccessUnit au;
  au.data.reserve(static_cast<size_t>(bytes));
  for (int i = 0; i < nal_count; ++i) {
    au.data.append(reinterpret_cast<const char*>(nals[i].p_payload), static_cast<size_t>(nals[i].i_payload));
  }
  au.key_frame = out.b_keyframe != 0;
  au.pts = out.i_pts;
  return au;
}

}  // namespace omniview::video
