#include "server/export/mcap_export.h"

#include <algorithm>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>

#include <opencv2/core/utility.hpp>
#include <set>

#include "core/cloud/colourer.h"
#include "core/gain/gain_compensator.h"
#include "core/io/image_codec.h"
#include "core/map/apply.h"
#include "core/map/fusion_map.h"
#include "core/mcap/mcap_writer.h"
#include "core/view/view.h"
#include "foxglove/omniview_schemas.pb.h"
#include "omniview/joint_states.pb.h"
#include "server/export/foxglove_content.h"
#include "server/video/h264_encoder.h"
#include "server/web/foxglove/foxglove_schema.h"

namespace omniview::export_mcap {

namespace {

constexpr uint64_t kSecond = 1000000000ull;

// One schema per message type, added on first use.
class Schemas {
 public:
  explicit Schemas(mcap::Writer& writer) : writer_(writer) {}
  uint16_t id(const google::protobuf::Descriptor* type) {
    auto it = ids_.find(type->full_name());
    if (it == ids_.end()) {
      it = ids_.emplace(type->full_name(),
                        writer_.add_schema(type->full_name(), "protobuf", foxglove_schema::descriptor_set(type)))
               .first;
    }
    return it->second;
  }

 private:
  mcap::Writer& writer_;
  std::map<std::string, uint16_t> ids_;
};

// The MCAP writer and its channels by topic, with the per-topic counts of the summary.
class Output {
 public:
  Output(const std::string& path, size_t chunk_bytes) : writer_(path, options(chunk_bytes)), schemas_(writer_) {}

  void write(const std::string& topic, const google::protobuf::Descriptor* type, uint64_t time_ns,
             const std::string& data) {
    auto it = channels_.find(topic);
    if (it == channels_.end()) it = channels_.emplace(topic, writer_.add_channel(schemas_.id(type), topic, "protobuf")).first;
    writer_.write(it->second, time_ns, time_ns, data);
    ++counts_[topic];
  }
  void close() { writer_.close(); }
  uint64_t bytes() const { return writer_.bytes_written(); }
  const std::map<std::string, uint64_t>& counts() const { return counts_; }

 private:
  static mcap::WriterOptions options(size_t chunk_bytes) {
    mcap::WriterOptions o;
    o.chunk_bytes = chunk_bytes;
    return o;
  }
  mcap::Writer writer_;
  Schemas schemas_;
  std::map<std::string, uint16_t> channels_;
  std::map<std::string, uint64_t> counts_;
};

// One view: its map for the current rig, its gains, and its encoder.
struct ViewRender {
  ViewSpec spec;
  std::unique_ptr<View> view;
  std::shared_ptr<const Rig> rig;  // what `map` was built for
  FusionMap map;
  GainCompensator gains;
  std::unique_ptr<video::H264Encoder> encoder;
  Pose T_robot_view = Pose::Identity();
  uint64_t last_key_ns = 0;
  std::string calibration;  // for the current rig

  void prepare(const std::shared_ptr<const Rig>& r) {
    if (rig == r) return;
    const std::string frame = spec.frame.empty() ? r->default_frame() : spec.frame;
    if (!r->frames().has_frame(frame)) {
      std::string known;
      for (const auto& f : r->frames().frames()) known += (known.empty() ? "" : ", ") + f;
      throw std::invalid_argument("view '" + spec.name + "': frame '" + frame +
                                  "' is not a frame of the recording's rig (frames: " + known + ")");
    }
    map = build_map(*r, *view);
    T_robot_view = r->frames().lookup(r->default_frame(), frame) * spec.T_frame_view();
    rig = r;
  }
};

double fps_of(const Recording& recording) {
  const auto& f = recording.frames;
  if (f.size() < 2) return 10;
  const double span = std::chrono::duration<double>(f.back().capture_time - f.front().capture_time).count();
  return span > 0 ? std::clamp((f.size() - 1) / span, 0.1, 120.0) : 10;
}

class Exporter {
 public:
  Exporter(const Recording& recording, const std::string& path, const ExportOptions& options)
      : recording_(recording), path_(path), options_(options) {
    for (const auto& spec : options.views) {
      auto v = std::make_unique<ViewRender>();
      v->spec = spec;
      try {
        v->view = View::create(spec);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("view '" + spec.name + "': " + e.what());
      }
      views_.push_back(std::move(v));
    }
    // Every view checked against the first rig before any frame is written.
    for (auto& v : views_) v->prepare(recording.rigs.at(recording.frames.front().rig_index));
    out_ = std::make_unique<Output>(path, options.chunk_bytes);  // last: a failure above leaves no file
  }

  ExportSummary run() {
    const size_t total = recording_.frames.size();
    // The next frame set is read (files, JPEG decoding, the cloud's PCD) on a thread of its
    // own while this one renders, encodes and writes the current one: on two cores the
    // export ran at 1.2 cores' worth before (bench/export_bench.cc).
    const auto load = [this](size_t i) { return this->load(recording_.frames[i]); };
    std::future<Loaded> next = std::async(std::launch::async, load, 0);
    for (size_t i = 0; i < total; ++i) {
      Loaded current = next.get();
      if (i + 1 < total) next = std::async(std::launch::async, load, i + 1);
      frame_set(recording_.frames[i], current);
      if (options_.progress) options_.progress(i + 1, total);
    }
    out_->close();
    summary_.frame_sets = total;
    summary_.messages = out_->counts();
    // A view no frame set could render (a black box snapshot of a robot whose views needed
    // other cameras) has no topic at all: said, so nobody looks for it in Foxglove.
    for (const auto& v : views_) {
      const std::string topic = "/views/" + v->spec.name;
      if (summary_.messages.count(topic) && summary_.messages.at(topic) > 0) continue;
      summary_.notes.push_back("view '" + v->spec.name + "': no frame set had every camera it needs, so the file has no " +
                               topic + " (a recording keeps the cameras the watched views used; `omniview record` "
                               "takes every camera)");
    }
    summary_.bytes = out_->bytes();
    return summary_;
  }

 private:
  // What one frame set brings from disk, read ahead of its turn.
  struct Loaded {
    std::vector<cv::Mat> images;
    std::vector<EncodedImage> encoded;
    std::shared_ptr<PointCloud> cloud;  // null: none recorded, or clouds not exported
  };

  Loaded load(const RecordingFrame& frame) const {
    Loaded l;
    l.images = recording_.load_images(frame, &l.encoded);
    if (options_.clouds && !frame.cloud_file.empty()) l.cloud = recording_.load_cloud(frame);
    return l;
  }

  void frame_set(const RecordingFrame& frame, Loaded& loaded) {
    const auto& rig = recording_.rigs.at(frame.rig_index);
    const uint64_t t = to_ns(frame.capture_time);
    if (summary_.start_ns == 0 || t < summary_.start_ns) summary_.start_ns = t;
    summary_.end_ns = std::max(summary_.end_ns, t);
    const std::vector<cv::Mat>& images = loaded.images;
    const std::vector<EncodedImage>& encoded = loaded.encoded;
    for (auto& v : views_) v->prepare(rig);

    if (rig != tf_rig_ || t >= last_tf_ns_ + kSecond) {
      std::vector<PosedView> posed;
      for (const auto& v : views_) posed.push_back({v->spec.name, v->T_robot_view});
      // The first also covers a cloud taken just before its frame set's images, so that
      // a viewer has the frames for every message from the start.
      uint64_t tf_time = t;
      if (!tf_rig_ && options_.clouds && !frame.cloud_file.empty()) tf_time = std::min(t, to_ns(frame.cloud_stamp));
      out_->write("/tf", foxglove::FrameTransforms::descriptor(), tf_time, frame_transforms(*rig, posed, tf_time));
      tf_rig_ = rig;
      last_tf_ns_ = t;
    }
    if (options_.cameras) cameras(*rig, images, encoded, t);
    render_views_and_cloud(images, t, rig, loaded.cloud);
    if (loaded.cloud) write_cloud(frame, *loaded.cloud);
    if (frame.joints && !frame.joints->empty()) {
      out_->write("/joint_states", omniview::JointStates::descriptor(), t, joint_states(*frame.joints, t));
    }
  }

  void cameras(const Rig& rig, const std::vector<cv::Mat>& images,
               const std::vector<EncodedImage>& encoded, uint64_t t) {
    for (size_t c = 0; c < rig.cameras().size() && c < images.size(); ++c) {
      if (images[c].empty()) continue;
      const Camera& camera = rig.cameras()[c];
      const std::string topic = "/cameras/" + camera.name;
      if (c < encoded.size() && encoded[c].bytes && !encoded[c].format.empty()) {
        const auto& b = *encoded[c].bytes;
        out_->write(topic + "/image", foxglove::CompressedImage::descriptor(), t,
                   compressed_image(camera.name, t, encoded[c].format,
                                    std::string_view(reinterpret_cast<const char*>(b.data()), b.size())));
      } else {
        const std::vector<uint8_t> jpeg = encode_jpeg(images[c], 90);
        out_->write(topic + "/image", foxglove::CompressedImage::descriptor(), t,
                   compressed_image(camera.name, t, "jpeg",
                                    std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size())));
      }
      const std::string calibration = camera_calibration(camera, t);
      if (!calibration.empty()) {
        out_->write(topic + "/calibration", foxglove::CameraCalibration::descriptor(), t, calibration);
      } else if (uncalibrated_.insert(camera.name).second) {
        summary_.notes.push_back("camera '" + camera.name + "': no /calibration (its " +
                                 describe(camera.model).camera_model + " + " + describe(camera.model).distortion_model +
                                 " model has no Foxglove CameraCalibration equivalent)");
      }
    }
  }

  // A view's messages for one frame set, made apart from the writer so that views render
  // side by side (one task per view; apply_map runs single-threaded when nested, as in the
  // daemon's render worker).
  struct Rendered {
    const google::protobuf::Descriptor* type = nullptr;
    std::string message, calibration;
    bool skipped = false;  // an image it needs is missing from the frame set
  };

  Rendered render(ViewRender& v, const std::vector<cv::Mat>& images, uint64_t t) {
    Rendered r;
    int channels = 1;
    for (size_t i = 0; i < v.map.camera_used.size(); ++i) {
      if (!v.map.camera_used[i]) continue;
      if (i >= images.size() || images[i].empty()) {
        r.skipped = true;
        return r;
      }
      channels = std::max(channels, images[i].channels());
    }
    cv::Mat image;
    apply_map(v.map, images, image, channels, v.gains.update(v.map, images, channels));
    const std::string optical = view_optical_frame(v.spec.name);
    if (options_.encoding == ViewEncoding::kJpeg) {
      const std::vector<uint8_t> jpeg = encode_jpeg(image, options_.quality);
      r.type = foxglove::CompressedImage::descriptor();
      r.message = compressed_image(optical, t, "jpeg",
                                   std::string_view(reinterpret_cast<const char*>(jpeg.data()), jpeg.size()));
    } else {
      if (!v.encoder) {
        video::H264Settings settings;
        settings.width = image.cols;
        settings.height = image.rows;
        settings.fps = fps_of(recording_);
        settings.crf = 51.0 - options_.quality / 2.0;  // as the daemon's streams (server/pipeline/video_stream.h)
        // One thread each: the views already encode side by side while the next frame set is
        // read; slice threads cost ~4 % more CPU here (bench/export_bench.cc).
        settings.threads = 1;
        v.encoder = std::make_unique<video::H264Encoder>(settings);
      }
      // A key frame (with SPS and PPS) a second, so a player can seek anywhere.
      const bool key = v.last_key_ns == 0 || t >= v.last_key_ns + kSecond;
      const video::AccessUnit au = v.encoder->encode(image, static_cast<int64_t>(t / 1000000), key);
      if (au.key_frame) v.last_key_ns = t;
      if (!au.data.empty()) {
        r.type = foxglove::CompressedVideo::descriptor();
        r.message = compressed_video(optical, t, au.data);
      }
    }
    r.calibration = view_calibration(*v.view, optical, t);
    return r;
  }

  // The views and the cloud's colouring side by side (one task each), then written in order.
  void render_views_and_cloud(const std::vector<cv::Mat>& images, uint64_t t, const std::shared_ptr<const Rig>& rig,
                              const std::shared_ptr<PointCloud>& cloud) {
    std::vector<Rendered> rendered(views_.size());
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const int tasks = static_cast<int>(views_.size()) + (cloud ? 1 : 0);
    cv::parallel_for_(cv::Range(0, tasks), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) {
        try {
          if (i == static_cast<int>(views_.size())) {
            colour(rig, *cloud, images);
          } else {
            rendered[i] = render(*views_[i], images, t);
          }
        } catch (...) {
          std::lock_guard lock(failure_mutex);
          if (!failure) failure = std::current_exception();
        }
      }
    });
    if (failure) std::rethrow_exception(failure);
    for (size_t i = 0; i < views_.size(); ++i) {
      const std::string topic = "/views/" + views_[i]->spec.name;
      if (rendered[i].skipped && missing_.insert(views_[i]->spec.name).second) {
        summary_.notes.push_back("view '" + views_[i]->spec.name +
                                 "': frame sets without an image of a camera it needs are skipped");
      }
      if (!rendered[i].type) continue;
      out_->write(topic, rendered[i].type, t, rendered[i].message);
      if (!rendered[i].calibration.empty()) {
        out_->write(topic + "/calibration", foxglove::CameraCalibration::descriptor(), t, rendered[i].calibration);
      }
    }
  }

  // On a task of its own beside the views: touches only the colourer and the cloud.
  void colour(const std::shared_ptr<const Rig>& rig, PointCloud& cloud, const std::vector<cv::Mat>& images) {
    if (!options_.colour_clouds || colour_failed_) return;
    try {
      if (colourer_rig_ != rig) {
        colourer_ = std::make_unique<CloudColourer>(rig);
        colourer_rig_ = rig;
      }
      colourer_->colour(cloud, CameraImages{images, {}}, ColourOptions{});
    } catch (const std::exception& e) {
      colour_failed_ = true;
      colour_failure_ = e.what();
    }
  }

  void write_cloud(const RecordingFrame& frame, const PointCloud& cloud) {
    if (colour_failed_ && !colour_failure_.empty()) {
      summary_.notes.push_back("clouds exported uncoloured: " + colour_failure_);
      colour_failure_.clear();  // said once
    }
    const uint64_t t = to_ns(frame.cloud_stamp);
    out_->write("/cloud", foxglove::PointCloud::descriptor(), t, point_cloud(cloud, t));
  }

  const Recording& recording_;
  std::string path_;
  const ExportOptions& options_;
  std::unique_ptr<Output> out_;
  std::vector<std::unique_ptr<ViewRender>> views_;
  std::shared_ptr<const Rig> tf_rig_;
  uint64_t last_tf_ns_ = 0;
  std::unique_ptr<CloudColourer> colourer_;
  std::shared_ptr<const Rig> colourer_rig_;
  bool colour_failed_ = false;
  std::string colour_failure_;  // for the summary's note, written once
  std::set<std::string> uncalibrated_, missing_;
  ExportSummary summary_;
};

}  // namespace

ExportSummary export_recording(const Recording& recording, const std::string& path, const ExportOptions& options) {
  if (options.quality < 1 || options.quality > 100) {
    throw std::invalid_argument("quality " + std::to_string(options.quality) + " is outside 1..100");
  }
  std::unique_ptr<Exporter> exporter;
  try {
    exporter = std::make_unique<Exporter>(recording, path, options);
    return exporter->run();
  } catch (...) {
    const bool created = exporter != nullptr;
    exporter.reset();  // closes the file
    if (created) {
      std::error_code ec;
      std::filesystem::remove(path, ec);
    }
    throw;
  }
}

}  // namespace omniview::export_mcap
