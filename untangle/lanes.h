// Four doubles in one vector (GCC vector extensions) and the element-wise helpers of the
// hex corner-tet lane kernels (untangle/tet_energy_lanes.cpp, the only file that includes it).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hexmesh::untangle {

// Four corner tets at a time, one per lane of a vector of doubles (GCC vector extensions:
// two SSE2 registers on baseline x86-64), with the same operations as the scalar code.
// These vectors never cross a call: every function taking or returning them is
// HEXMESH_LANE_INLINE (below), which is what makes the AVX2 build safe, since an AVX2
// caller would pass them in a register a baseline callee reads from memory. So the ABI
// note about passing them without AVX does not apply (GCC reports it at the end of the
// file: ignored from here on). A new helper on Lanes must be HEXMESH_LANE_INLINE too.
#pragma GCC diagnostic ignored "-Wpsabi"
using Lanes = double __attribute__((vector_size(32)));
using LaneInts = int64_t __attribute__((vector_size(32)));  // comparison results
using LaneBits = uint64_t __attribute__((vector_size(32)));
constexpr int lane_count = 4;

// The lane kernels are inlined into hex_sum, which is built twice: for the baseline and, on
// x86-64, for AVX2 (one 4-double register per vector instead of two SSE2 ones); hex_energy
// and hex_energy_hessian call the second where the CPU has AVX2. The same IEEE operations run
// in the same order (no FMA: contracting a * b + c would round differently; the project
// builds without -march or -mfma), so both give the same bits. Only hex_sum_avx2 is built
// for AVX2: nothing built for it can be linked into a baseline path.
#define HEXMESH_LANE_INLINE __attribute__((always_inline)) inline

HEXMESH_LANE_INLINE Lanes lane_sqrt(Lanes x) {
#if defined(__SSE2__)
    __m128d half[2];
    std::memcpy(half, &x, sizeof x);
    half[0] = _mm_sqrt_pd(half[0]);
    half[1] = _mm_sqrt_pd(half[1]);
    std::memcpy(&x, half, sizeof x);
#else
    for (int l = 0; l < lane_count; ++l) x[l] = std::sqrt(x[l]);
#endif
    return x;
}

HEXMESH_LANE_INLINE bool any_lane(LaneInts mask) {
    for (int l = 0; l < lane_count; ++l)
        if (mask[l]) return true;
    return false;
}

// inverse_cbrt (untangle/tet_energy.cpp) in every lane.
HEXMESH_LANE_INLINE Lanes inverse_cbrt(Lanes x) {
    LaneBits bits;  // unsigned: the shifts are logical, also in NaN lanes
    std::memcpy(&bits, &x, sizeof x);
    bits = 0x553eeeeeeeeef000ULL - ((((bits >> 32) * 0xAAAAAAABULL) >> 33) << 32);
    Lanes y;
    std::memcpy(&y, &bits, sizeof y);
    for (int k = 0; k < 3; ++k) {
        const Lanes r = 1 - x * y * y * y;
        y *= 1 + r * (1.0 / 3 + r * (2.0 / 9));
    }
    const LaneInts normal = (x > 1e-300) & (x < 1e300);
    if (!any_lane(~normal)) return y;
    for (int l = 0; l < lane_count; ++l)
        if (!normal[l]) y[l] = 1 / std::cbrt(x[l]);
    return y;
}

HEXMESH_LANE_INLINE Lanes lane_abs(Lanes x) {
    return x < 0 ? -x : x;
}
HEXMESH_LANE_INLINE Lanes lane_max(Lanes x, Lanes y) {
    return x > y ? x : y;
}

}  // namespace hexmesh::untangle
