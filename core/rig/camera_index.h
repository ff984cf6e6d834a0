// The one "no camera" index, shared by view maps and coloured clouds (both store a rig
// camera index in a byte, so a rig may have up to 254 cameras).
#pragma once

#include <cstdint>

namespace omniview {

inline constexpr uint8_t kNoCamera = 255;

}  // namespace omniview
