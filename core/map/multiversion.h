// OMNIVIEW_MULTIVERSION: compile a hot function for baseline x86-64 and for x86-64-v3
// (AVX2, FMA), chosen once at load time by the CPU it runs on. Portable binaries, no
// -march=native; a no-op on other architectures and compilers without target_clones.
#pragma once

// Off in ThreadSanitizer trees, also in the files they build without its checks
// (OMNIVIEW_NO_MULTIVERSION, core/CMakeLists.txt).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_THREAD__) && !defined(OMNIVIEW_NO_MULTIVERSION) && \
    ((!defined(__clang__) && __GNUC__ >= 12) || (defined(__clang__) && __clang_major__ >= 14))
#define OMNIVIEW_MULTIVERSION __attribute__((target_clones("default", "arch=x86-64-v3")))
#else
#define OMNIVIEW_MULTIVERSION
#endif
