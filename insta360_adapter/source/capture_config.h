// The config keys of `type: insta360` and `type: v4l2` (documented in config/insta360.yaml
// and config/omniviewd.yaml), read into CaptureSettings.
//
//   - name: air
//     type: insta360
//     device: name:Insta360        # /dev/video2 | 2e1a:1000 (USB vendor:product) | serial:XYZ | name:PART
//     file: recordings/air         # instead of device: a folder of JPEGs or an MJPEG file
//     rate_hz: 30  speed: 1  loop: true    # file only: playback
//     calibration: my_camchain.yaml        # default (insta360): the built-in nominal Air calibration
//     rig_frame: base_link                 # the robot frame the camera is mounted in
//     mount: [x, y, z, yaw, pitch, roll]   # the camera body in rig_frame (m, deg)
//     format: {pixel_format: MJPG, width: 3008, height: 1504, fps: 30}
//     lenses: {front: [0, 0, 1504, 1504], back: [1504, 0, 1504, 1504]}   # crops [x, y, w, h]
//     decode_scale: auto                   # auto | 1 | 2 | 4
//     lens_check: true
#pragma once

#include <memory>

#include "insta360_adapter/source/capture_source.h"
#include "server/source/source_registry.h"

namespace omniview::insta360 {

// Throws ConfigError naming file, line and key. `open_override`, when set, replaces the
// device the config names (tests inject a fake camera through it).
CaptureSettings read_capture_settings(const SourceConfig& config, const std::string& type,
                                      DeviceOpener open_override = nullptr);

std::unique_ptr<Source> make_insta360_source(const SourceConfig& config);
std::unique_ptr<Source> make_v4l2_source(const SourceConfig& config);

// The built-in nominal Air calibration (config/insta360/air_calibration.yaml, compiled in).
Rig default_air_calibration();

// `calibration` placed on the robot: its cameras and frames, with its body frame hung
// from `rig_frame` at `mount` (nothing to hang when they are the same frame).
Rig place_rig(const Rig& calibration, const std::string& rig_frame, const Pose& mount);

}  // namespace omniview::insta360
