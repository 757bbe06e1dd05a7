// Runtime SIMD dispatch: which instruction set the hot loops run on.
//
// The hot kernels are compiled once per target (Highway's foreach_target: scalar, SSE4, AVX2,
// AVX-512 on x86-64; NEON on Arm) into one binary, and every call goes to the best target this
// CPU supports. PENUMBRA_SIMD pins one target for the whole process — Penumbra's kernels and
// Embree's alike — so a machine with AVX-512 can measure what a machine without it runs.
#pragma once

#include <string>
#include <vector>

namespace penumbra::simd {

/// Applies PENUMBRA_SIMD (scalar | sse4 | avx2 | avx512; unset or empty: the best this CPU
/// has). Throws penumbra::Error for an unknown name or a target this CPU or build lacks.
/// Idempotent; call it before the first frame.
void configure_from_environment();

/// Pins dispatched code to `name` (as PENUMBRA_SIMD); "" restores the best target. Throws as above.
void pin(const std::string& name);

/// The target dispatched code runs on now: "scalar", "SSE4", "AVX2", "AVX-512", "NEON", ...
std::string active_target();

/// True where the dispatched target is AVX2 or better (x86-64): for code that picks an AVX2 library
/// routine itself (libmvec's vector atan2).
bool at_least_avx2();

/// The PENUMBRA_SIMD names usable on this CPU with this build, best first.
std::vector<std::string> available();

/// Embree's `isa=` device setting for the pinned target ("" when nothing is pinned: Embree
/// chooses the best itself).
std::string embree_isa();

}  // namespace penumbra::simd
