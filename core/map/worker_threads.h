// How many threads build and apply maps. They run on OpenCV's thread pool, which uses every
// core by default; on a robot that shares its computer with other software, an integrator
// caps it with the environment variable OMNIVIEW_THREADS (1 = everything on the calling
// thread). omniviewd and omniview read it at start.
#pragma once

namespace omniview {

// Applies OMNIVIEW_THREADS if it is set (a whole number >= 1); throws std::invalid_argument
// naming the variable for anything else. Unset: OpenCV's default (all cores).
void apply_worker_threads_from_env();

}  // namespace omniview
