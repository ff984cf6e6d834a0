// AVX2 rows for apply(): eight output pixels per step, their source pixels fetched with
// gathers. Compiled with a per-function target attribute and used only where the CPU says
// it has AVX2 (apply.cc asks once), so the binary still runs on baseline x86-64.
// Not part of the public API.
#pragma once

#include <cstdint>

#include "core/map/fusion_map.h"

namespace omniview::apply_internal {

// All used sources (camera i at pyramid level l is source i + l * cameras) as 32-bit byte
// offsets from one base pointer, so one gather serves pixels from different cameras. Up
// to 8 sources; built by apply.cc.
struct GatherSources {
  const uint8_t* base = nullptr;
  int32_t delta[8] = {};   // camera image start - base, in bytes
  int32_t stride[8] = {};  // bytes per row
  int32_t last_wide[8] = {};  // last offset from base an 8-byte read may start at in the image
};

// Tests switch the SIMD rows off to check the portable ones on the same machine.
void set_simd_enabled(bool enabled);
bool simd_enabled();

#if defined(__x86_64__) && defined(__GNUC__)
#define OMNIVIEW_APPLY_AVX2 1

// True where the running CPU has AVX2.
bool have_avx2();

// Nearest-centre rows whose sources all have the output's channel count. Entries with
// cam == kNoCamera give black; n may be any length (the tail goes pixel by pixel).
void apply_row_bgr_avx2(const MapEntry* m, int n, const GatherSources& s, int cameras, uint8_t* out);
void apply_row_grey_avx2(const MapEntry* m, int n, const GatherSources& s, int cameras, uint8_t* out);
#endif

}  // namespace omniview::apply_internal
