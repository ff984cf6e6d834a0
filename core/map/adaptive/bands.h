// Adaptive map building (nearest-centre, and blend outside the cameras' overlaps).
//
// Camera models and surfaces are smooth, so inside most 8x8 blocks of the output the
// source coordinates are almost exactly a bilinear function of the pixel position. The
// builder evaluates the models exactly at the block corners, edge midpoints and centres
// (under a tenth of the pixels) and interpolates inside a block only when all agree
// (block_plan.h):
//   - the same camera wins at all four corners and at the centre;
//   - at the centre and the four edge midpoints the interpolated coordinates lie within
//     kTolerancePx of the exact ones (bilinear error peaks there for smooth maps; the
//     midpoints catch saddle-shaped maps whose error cancels at the centre);
//   - that camera's mask, if it has one, allows every interpolated pixel.
// A full 8x8 block that fails gets a lattice twice as fine (5x5). Where all 25 samples
// see one camera, one biquadratic patch through 9 of them may cover it if the other 16
// are within the tolerance (strong curvature: a 360 deg fisheye view's outer rings);
// else each 4x4 quarter is planned as a block, interpolated only where its own midpoints
// are within the tolerance (a seam's block keeps exact pixels only where it must).
// Every other pixel (seams, coverage edges, fisheye circles, masks) is computed exactly.
// Patches are encoded straight into the map (patch_writer.h); lattice rows are shared by
// consecutive bands; exact pixels of a row are projected as one batch (winners.h).
// Blend maps: a block is interpolated only where one camera sees all its samples (there the
// blend is that camera at full weight); a block two cameras see at a sample is exact, each
// of its pixels by the blend rule (blend_pixels.h), as are the exact pixels two cameras see.
// The image border needs no test: a bilinear patch whose corners lie inside the image
// stays inside it. Near a seam an interpolated block may keep a camera whose neighbour
// would win by a hair; both see the point, so the picture is the same.
#pragma once

#include <cstdint>
#include <vector>

#include "core/map/map_kernels.h"

namespace omniview::map_internal {

// Bands [band_begin, band_end) of kBlock rows each (rows ys[b] .. ys[b + 1] - 1 of the
// grid lines 0, 8, ..., H - 1; the last band also owns row H - 1). Consecutive bands share
// their lattice rows, so a worker should take a run of them. Sets used[c] for every camera
// c the rows read.
// `occlusion` (optional): as build_map's; see BandBuilder::may_interpolate for what it adds.
// `blend`: a blend map (map.secondary and primary_weight allocated, black and 256 where a
// single camera sees the pixel, which the builder leaves as they are): a block is
// interpolated only where a single camera sees all its samples, every other pixel gets the
// blend rule's entries exactly (blend_pixels.h).
void build_bands_adaptive(const View& view, const std::vector<CameraSetup>& setups, FusionMap& map, int band_begin,
                          int band_end, std::vector<uint8_t>& used, const Occlusion* occlusion = nullptr,
                          bool blend = false);

// Number of bands of a map of `height` rows (>= 2).
inline int adaptive_band_count(int height) { return (height - 2) / kBlock + 1; }

}  // namespace omniview::map_internal
