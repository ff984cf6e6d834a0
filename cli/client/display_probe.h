// Whether the X display named by DISPLAY answers, before OpenCV's HighGUI tries it: its Qt
// back end aborts the process when it cannot connect (a stale `ssh -X` forwarding, a display
// that is gone), where `omniview show` should say what to do instead.
#pragma once

#include <string>

namespace omniview::cli {

// "" when `display` (a DISPLAY value: "[host]:N[.screen]") accepts a connection within about
// a second; otherwise why not, for a person ("nothing listens on /tmp/.X11-unix/X99").
std::string probe_x_display(const std::string& display);

}  // namespace omniview::cli
