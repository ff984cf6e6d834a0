// insta360-lens-check: finds each lens' image circle in a frame of a dual fisheye (or any
// fisheye) camera and says how far the calibration's principal point is from its centre;
// --fit writes the calibration with the principal points moved onto the circles.
//
//   insta360-lens-check --frame frame.jpg [--calibration camchain_or_rig.yaml] [--fit fixed.yaml]
//
// Grab a frame with e.g. `ffmpeg -f v4l2 -input_format mjpeg -video_size 3008x1504 -i
// /dev/video2 -frames:v 1 frame.jpg`, of a bright scene (the circle's rim must show).
#include <fstream>
#include <iostream>
#include <iterator>

#include "core/rig/rig.h"
#include "insta360_adapter/decode/jpeg_decoder.h"
#include "insta360_adapter/rig/lens_circle.h"
#include "insta360_adapter/rig/lens_layout.h"
#include "insta360_adapter/source/capture_config.h"

using namespace omniview;
using namespace omniview::insta360;

int main(int argc, char** argv) {
  std::string frame_file, calibration_file, fit_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "insta360-lens-check: " << a << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--frame") frame_file = value();
    else if (a == "--calibration") calibration_file = value();
    else if (a == "--fit") fit_file = value();
    else {
      std::cerr << "usage: insta360-lens-check --frame FRAME.jpg [--calibration FILE.yaml] [--fit OUT.yaml]\n"
                   "  Compares each lens' image circle with the calibration (default: the built-in nominal\n"
                   "  Insta360 Air calibration); --fit writes the calibration with the principal points\n"
                   "  moved onto the circle centres (our rig YAML).\n"
                   "  Exit status: 0 fine (or --fit written), 3 a lens more than 3 px off, 1 an error.\n";
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (frame_file.empty()) {
    std::cerr << "insta360-lens-check: --frame is required (see --help)\n";
    return 2;
  }
  try {
    Rig calibration = calibration_file.empty() ? default_air_calibration() : load_rig(calibration_file, "insta360");
    std::ifstream in(frame_file, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.empty()) throw std::runtime_error(frame_file + ": cannot read");
    JpegDecoder decoder;
    const cv::Mat image = decoder.decode(bytes.data(), bytes.size());
    const auto crops = side_by_side(calibration);
    check_crops(calibration, crops, image.size());
    bool all_found = true, any_off = false;
    for (const auto& crop : crops) {
      const LensCircleReport r = check_lens_circle(*calibration.find(crop.camera), image, crop.rect);
      std::cout << describe(r) << "\n";
      all_found = all_found && r.found;
      any_off = any_off || (r.found && r.offset_px > kLensOffsetWarnPx);
    }
    if (!fit_file.empty()) {
      if (!all_found) throw std::runtime_error("not every lens circle was found: nothing written");
      Rig fixed(calibration.default_frame());
      for (const auto& crop : crops) {
        Camera cam = *calibration.find(crop.camera);
        const LensCircleReport r = check_lens_circle(cam, image, crop.rect);
        cam.model = shift_and_scale(cam.model, r.circle_centre - r.principal_point, 1);
        fixed.add_camera(std::move(cam));
      }
      save_rig_yaml(fixed, fit_file);
      std::cout << "wrote " << fit_file << " (give it to the source as `calibration:`)\n";
      return 0;
    }
    // For scripts: 3 when a lens sits further off than the daemon warns about.
    return any_off ? 3 : 0;
  } catch (const std::exception& e) {
    std::cerr << "insta360-lens-check: " << e.what() << "\n";
    return 1;
  }
}
