#include "tests/video/h264_decoder.h"

#include <cmath>
#include <limits>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/imgutils.h>
}

namespace omniview::testing {

struct H264Decoder::Av {
  const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
  AVCodecContext* context = nullptr;
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  ~Av() {
    av_frame_free(&frame);
    av_packet_free(&packet);
    avcodec_free_context(&context);
  }
};

namespace {
std::string av_text(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof text);
  return text;
}
}  // namespace

H264Decoder::H264Decoder() : av_(std::make_unique<Av>()) {
  if (av_->codec == nullptr) throw std::runtime_error("libavcodec has no H.264 decoder");
  av_->context = avcodec_alloc_context3(av_->codec);
  // A picture out of every packet, as a live player wants: no frame threading delay.
  av_->context->thread_count = 1;
  av_->context->flags |= AV_CODEC_FLAG_LOW_DELAY;
  // Report broken references rather than hide them.
  av_->context->err_recognition = AV_EF_EXPLODE | AV_EF_CRCCHECK | AV_EF_BITSTREAM;
  av_->context->flags2 |= AV_CODEC_FLAG2_SHOW_ALL;
  if (avcodec_open2(av_->context, av_->codec, nullptr) < 0) throw std::runtime_error("cannot open the H.264 decoder");
}

H264Decoder::~H264Decoder() = default;

cv::Mat H264Decoder::decode(const std::string& access_unit) {
  av_packet_unref(av_->packet);
  if (av_new_packet(av_->packet, static_cast<int>(access_unit.size())) < 0) throw std::bad_alloc();
  std::copy(access_unit.begin(), access_unit.end(), av_->packet->data);
  int r = avcodec_send_packet(av_->context, av_->packet);
  av_packet_unref(av_->packet);
  if (r < 0) {
    ++errors_;
    last_error_ = "send_packet: " + av_text(r);
    return {};
  }
  r = avcodec_receive_frame(av_->context, av_->frame);
  if (r == AVERROR(EAGAIN)) return {};
  if (r < 0) {
    ++errors_;
    last_error_ = "receive_frame: " + av_text(r);
    return {};
  }
  AVFrame* f = av_->frame;
  if (f->decode_error_flags != 0 || (f->flags & AV_FRAME_FLAG_CORRUPT) != 0) {
    ++errors_;
    ++corrupt_;
    last_error_ = "a corrupt picture (a missing reference)";
  }
  if (f->format != AV_PIX_FMT_YUV420P && f->format != AV_PIX_FMT_YUVJ420P) {
    ++errors_;
    last_error_ = "not a 4:2:0 picture: format " + std::to_string(f->format);
    av_frame_unref(f);
    return {};
  }
  full_range_ = f->color_range == AVCOL_RANGE_JPEG || f->format == AV_PIX_FMT_YUVJ420P;
  const int w = f->width, h = f->height;
  cv::Mat i420(h * 3 / 2, w, CV_8UC1);
  for (int y = 0; y < h; ++y) std::copy_n(f->data[0] + y * f->linesize[0], w, i420.ptr(y));
  uint8_t* u = i420.data + static_cast<size_t>(w) * h;
  uint8_t* v = u + static_cast<size_t>(w / 2) * (h / 2);
  for (int y = 0; y < h / 2; ++y) {
    std::copy_n(f->data[1] + y * f->linesize[1], w / 2, u + y * (w / 2));
    std::copy_n(f->data[2] + y * f->linesize[2], w / 2, v + y * (w / 2));
  }
  av_frame_unref(f);
  return i420;
}

cv::Mat H264Decoder::luma(const cv::Mat& i420, int width, int height) {
  return cv::Mat(height, width, CV_8UC1, const_cast<uint8_t*>(i420.data));
}

double psnr(const cv::Mat& a, const cv::Mat& b) {
  if (a.size() != b.size() || a.type() != b.type()) return 0;
  double sum = 0;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      const double d = double(a.at<uint8_t>(y, x)) - b.at<uint8_t>(y, x);
      sum += d * d;
    }
  }
  if (sum == 0) return std::numeric_limits<double>::infinity();
  return 10 * std::log10(255.0 * 255.0 / (sum / (double(a.rows) * a.cols)));
}

}  // namespace omniview::testing
