// PSNR bounds of the golden tests, in dB, over the view pixels some camera covers.
//
// Where they come from. The camera images are ray-cast with 3x3 supersampling and stored
// in 8 bits; a view resamples them bilinearly, which low-passes the texture wherever a
// camera pixel covers more of the surface than a view pixel does (fisheye rims, the
// low-resolution centre of the Mei/omni lens, floors seen at grazing angles). With correct
// geometry the measured PSNRs range from ~35 dB (Spot's floor) to ~54 dB (the tests print
// every figure, per camera too). Each bound sits about 4 dB below what was measured: room
// for compiler, libm and OpenCV differences, not for a calibration error. One pixel of yaw
// on one lens takes the dual-fisheye panorama from 53.4 to 40.3 dB (that lens alone to 37.4;
// OnePixelOfCalibrationErrorFailsTheBound), and the naive back-to-back stitch of the paper's
// Fig. 4 to 18.8 dB.
#pragma once

namespace omniview {

// Dual fisheye panorama: measured 53.4 (blend 53.4; grey, colour and mixed inputs 53.5-54.3).
inline constexpr double kDualFisheyeBoundDb = 49;
inline constexpr double kNaiveStitchMarginDb = 20;  // the naive stitch measured 34.6 below ours
inline constexpr double kMaskedBoundDb = 41;        // measured 45.7: the back lens' compressed rim
inline constexpr double kSpotFloorBoundDb = 31;     // measured 35.5 (frontleft alone 31.2: grazing)
inline constexpr double kSpotWallBoundDb = 49;      // measured 53.7
inline constexpr double kCylindricalBoundDb = 38;   // measured 42.8
inline constexpr double kMercatorBoundDb = 39;      // measured 43.9
inline constexpr double kFisheyeBoundDb = 38;       // measured 42.7
// Each camera of the mixed-model ring over its share of a panorama: lowest measured 39.8
// (omni, whose Mei projection has the coarsest centre: f / (1 + xi) = 126 px/rad).
inline constexpr double kPerCameraModelBoundDb = 35;
// A perspective view straight through one ring camera: measured 47.9 (omni) to 52.7.
inline constexpr double kPerspectivePerModelBoundDb = 43;

}  // namespace omniview
