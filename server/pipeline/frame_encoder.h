// Turns a rendered view image into the bytes of one encoding (done once per view frame
// and distinct EncodingKey, however many clients share it).
#pragma once

#include <string>

#include <opencv2/core/mat.hpp>

#include "server/pipeline/subscriber.h"

namespace omniview {

// `image` is CV_8UC1 or CV_8UC3 (BGR). Fills encoding, width, height, channels and data of
// `frame`. Throws std::runtime_error if the codec fails.
void encode_frame(const cv::Mat& image, const EncodingKey& key, v1::Frame& frame);

// Checks and normalises a client's request: unspecified encoding → JPEG, quality 0 → 85
// (H264: 56, CRF 23). `max_kbps` is H264's bitrate ceiling (0: none), refused for the
// others; the caller sets an H264 key's rate_mhz. Throws std::invalid_argument with a
// message for a bad quality, bitrate or encoding.
EncodingKey encoding_key(v1::Encoding encoding, int quality, bool gray, int max_kbps = 0);

std::string to_string(const EncodingKey& key);

}  // namespace omniview
