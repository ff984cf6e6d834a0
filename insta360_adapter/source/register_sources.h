// Registers the adapter's source types (`insta360`, `v4l2`) with the daemon's registry;
// omniviewd's main calls it at start-up.
#pragma once

namespace omniview::insta360 {

void register_insta360_sources();

}  // namespace omniview::insta360
