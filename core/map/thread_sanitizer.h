// ThreadSanitizer's range checks, for code compiled without its per-access instrumentation
// (core/CMakeLists.txt: the pixel rows of apply_map). No-ops in every other build.
#pragma once

#include <cstddef>

#if defined(__SANITIZE_THREAD__)
extern "C" void __tsan_read_range(void* addr, unsigned long size);   // NOLINT: the runtime's names
extern "C" void __tsan_write_range(void* addr, unsigned long size);  // NOLINT
#endif

namespace omniview::thread_sanitizer {

#if defined(__SANITIZE_THREAD__)
inline constexpr bool active = true;
// Checks `bytes` at `data` as read (written) by the calling thread, as if it touched each.
inline void reads(const void* data, size_t bytes) {
  if (bytes > 0) __tsan_read_range(const_cast<void*>(data), bytes);
}
inline void writes(void* data, size_t bytes) {
  if (bytes > 0) __tsan_write_range(data, bytes);
}
#else
inline constexpr bool active = false;
inline void reads(const void*, size_t) {}
inline void writes(void*, size_t) {}
#endif

}  // namespace omniview::thread_sanitizer
