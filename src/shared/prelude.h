// The portable dialect of src/shared/ (STYLE.md rule 2): one source read by C++, CUDA and GLSL.
// Shared code is written as GLSL-flavoured C: plain structs, free functions marked DAISY_HD,
// parameters as DAISY_IN(T) (read-only) or DAISY_INOUT(T) (read-write), fixed-size local arrays,
// no recursion, templates, STL, exceptions, virtuals or default arguments. Write `float(x)`,
// `int(x)`, `uint(x)` conversions, `u` on unsigned literals, `atan(y, x)` for the two-argument
// arc tangent, and never name a variable after a GLSL keyword (`patch`, `sample`, `centroid`,
// `shared`, `input`, `output`, `filter`). Structs are built field by field: GLSL has neither
// brace initialisers nor constructors for user structs.
// Include guards rather than #pragma once: glslang's #include extension needs them.
#ifndef DAISY_SHARED_PRELUDE_H
#define DAISY_SHARED_PRELUDE_H

#if defined(GL_core_profile) || defined(VULKAN) || defined(DAISY_GLSL)

// ---- GLSL: the built-in vector types and functions are the vocabulary; nothing to define.
#ifndef DAISY_GLSL
#define DAISY_GLSL 1
#endif
#define DAISY_HD
#define DAISY_IN(T) in T
#define DAISY_INOUT(T) inout T
#define DAISY_SHARED_BEGIN
#define DAISY_SHARED_END
// A read-only GPU buffer of T reached through a 64-bit device address: `DAISY_BUFFER(Name, T);`
// declares the type Name, read as `buf.v[k]` in both languages. The including shader must enable
// GL_EXT_buffer_reference, GL_EXT_scalar_block_layout (scalar layout matches the C++ structs,
// gpu_types.h) and GL_EXT_shader_explicit_arithmetic_types_int64 (uint64_t addresses), plus
// GL_GOOGLE_include_directive for the #includes; it can construct a Name from a uint64_t.
#define DAISY_BUFFER(Name, T)                                                           \
    layout(buffer_reference, scalar, buffer_reference_align = 4) readonly buffer Name { \
        T v[];                                                                          \
    }
// uint64_t is a built-in type under GL_EXT_shader_explicit_arithmetic_types_int64.

#else

// ---- C++ and CUDA: a minimal GLSL-like vocabulary in namespace daisy::shared.
#include <math.h>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#if defined(__CUDACC__)
#define DAISY_HD __host__ __device__ inline
#else
#define DAISY_HD inline
#endif
#define DAISY_IN(T) const T&
#define DAISY_INOUT(T) T&
#define DAISY_SHARED_BEGIN namespace daisy::shared {
#define DAISY_SHARED_END }
// A read-only device buffer of T: in C++ a plain pointer to the host (or CUDA device) array, read
// as `buf.v[k]` as in GLSL. `DAISY_BUFFER(Name, T);` declares the type Name (GLSL side above).
#define DAISY_BUFFER(Name, T) \
    struct Name {             \
        const T* v;           \
    }

namespace daisy::shared {

using uint = std::uint32_t;
// GLSL's uint64_t (GL_EXT_shader_explicit_arithmetic_types_int64): device addresses.
using uint64_t = std::uint64_t;

// Float math under GLSL's names. The C functions (sqrtf, ...) exist in CUDA device code too.
DAISY_HD float sqrt(float x) {
    return sqrtf(x);
}
DAISY_HD float abs(float x) {
    return fabsf(x);
}
DAISY_HD int abs(int x) {
    return x < 0 ? -x : x;
}
// min and max as the compare-and-select that x86's minss/maxss are (no libm call): the first
// argument when either is NaN, so max(0.0f, x) and min(1.0f, x) map a NaN x to the constant, as
// fmaxf/fminf did; clamp maps NaN to lo.
DAISY_HD float min(float a, float b) {
    return b < a ? b : a;
}
DAISY_HD float max(float a, float b) {
    return b > a ? b : a;
}
DAISY_HD int min(int a, int b) {
    return a < b ? a : b;
}
DAISY_HD int max(int a, int b) {
    return a > b ? a : b;
}
DAISY_HD uint min(uint a, uint b) {
    return a < b ? a : b;
}
DAISY_HD uint max(uint a, uint b) {
    return a > b ? a : b;
}
DAISY_HD float clamp(float x, float lo, float hi) {
    return min(max(lo, x), hi);
}
DAISY_HD int clamp(int x, int lo, int hi) {
    return x < lo ? lo : (x > hi ? hi : x);
}
DAISY_HD float sin(float x) {
    return sinf(x);
}
DAISY_HD float cos(float x) {
    return cosf(x);
}
DAISY_HD float floor(float x) {
    return floorf(x);
}
DAISY_HD float sign(float x) {
    return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f);
}

// 2-vector, GLSL's vec2. Only what the shared kernels use.
struct vec2 {
    float x, y;
    vec2() = default;
    DAISY_HD constexpr vec2(float xValue, float yValue) : x(xValue), y(yValue) {}
    DAISY_HD constexpr explicit vec2(float s) : x(s), y(s) {}
};

// 3-vector, GLSL's vec3 (12 bytes, scalar layout: matches GL_EXT_scalar_block_layout).
struct vec3 {
    float x, y, z;
    vec3() = default;
    DAISY_HD constexpr vec3(float xValue, float yValue, float zValue)
        : x(xValue), y(yValue), z(zValue) {}
    DAISY_HD constexpr explicit vec3(float s) : x(s), y(s), z(s) {}
    DAISY_HD vec3& operator+=(const vec3& o) { return x += o.x, y += o.y, z += o.z, *this; }
    DAISY_HD vec3& operator-=(const vec3& o) { return x -= o.x, y -= o.y, z -= o.z, *this; }
    DAISY_HD vec3& operator*=(float s) { return x *= s, y *= s, z *= s, *this; }
};
static_assert(sizeof(vec2) == 8 && std::is_trivially_copyable_v<vec2>);
static_assert(sizeof(vec3) == 12 && std::is_trivially_copyable_v<vec3>);
static_assert(std::is_standard_layout_v<vec3> && std::is_trivially_default_constructible_v<vec3>);

DAISY_HD vec2 operator+(vec2 a, vec2 b) {
    return vec2(a.x + b.x, a.y + b.y);
}
DAISY_HD vec2 operator-(vec2 a, vec2 b) {
    return vec2(a.x - b.x, a.y - b.y);
}
DAISY_HD vec2 operator*(vec2 a, float s) {
    return vec2(a.x * s, a.y * s);
}
DAISY_HD vec2 operator*(float s, vec2 a) {
    return vec2(a.x * s, a.y * s);
}

DAISY_HD vec3 operator+(vec3 a, vec3 b) {
    return vec3(a.x + b.x, a.y + b.y, a.z + b.z);
}
DAISY_HD vec3 operator-(vec3 a, vec3 b) {
    return vec3(a.x - b.x, a.y - b.y, a.z - b.z);
}
DAISY_HD vec3 operator-(vec3 a) {
    return vec3(-a.x, -a.y, -a.z);
}
DAISY_HD vec3 operator*(vec3 a, vec3 b) {
    return vec3(a.x * b.x, a.y * b.y, a.z * b.z);
}
DAISY_HD vec3 operator*(vec3 a, float s) {
    return vec3(a.x * s, a.y * s, a.z * s);
}
DAISY_HD vec3 operator*(float s, vec3 a) {
    return vec3(a.x * s, a.y * s, a.z * s);
}
DAISY_HD vec3 operator/(vec3 a, float s) {
    return vec3(a.x / s, a.y / s, a.z / s);
}

DAISY_HD float dot(vec2 a, vec2 b) {
    return a.x * b.x + a.y * b.y;
}
DAISY_HD float dot(vec3 a, vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
DAISY_HD vec3 cross(vec3 a, vec3 b) {
    return vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
DAISY_HD float length(vec3 a) {
    return sqrtf(dot(a, a));
}
DAISY_HD float distance(vec3 a, vec3 b) {
    return length(a - b);
}
DAISY_HD vec3 normalize(vec3 a) {
    return a * (1.0f / length(a));
}
DAISY_HD vec3 mix(vec3 a, vec3 b, float t) {
    return a + (b - a) * t;
}

}  // namespace daisy::shared

#endif

// ---- All three dialects.
DAISY_SHARED_BEGIN

// The shared code's two-argument arc tangent, one definition for C++, CUDA and GLSL (written as
// `atan(y, x)`): the C library's atan2f is a call (13-18% of the cpu backend's view-factor time),
// and Vulkan lets a driver's atan be off by 4096 ULP (Vulkan spec, "Precision and Operation of
// SPIR-V Instructions"; lavapipe's moved F_ij by up to 3e-4 relative). Cephes' atanf polynomial
// (Moshier, Cephes Math Library, atanf.c) on [-tan(pi/8), tan(pi/8)]: with m = min(|x|, |y|)
// and M = max, atan(m / M), or pi/4 + atan((m - M) / (m + M)) when m / M > tan(pi/8), so one
// division; then the octant. Measured against double atan2: below 2.5e-7 relative (about 2 ULP)
// over the finite range (tests/shared/atan_test.cpp). Finite arguments; atan(0, 0) = 0, and a
// negative zero x counts as +0 (atan(0, -0) = 0, not pi).
DAISY_HD float daisyAtan2(float y, float x) {
    float ax = abs(x);
    float ay = abs(y);
    float greater = max(ax, ay);
    float lesser = min(ax, ay);
    bool upper = lesser > 0.414213562f * greater;  // tan(pi/8)
    float num = upper ? lesser - greater : lesser;
    float den = upper ? lesser + greater : greater;
    float a = den > 0.0f ? num / den : 0.0f;  // in [-tan(pi/8), tan(pi/8)]
    float z = a * a;
    float p = ((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z -
        3.33329491539e-1f;
    float r = (upper ? 0.785398163f : 0.0f) + (a + a * z * p);
    r = ay > ax ? 1.57079633f - r : r;
    r = x < 0.0f ? 3.14159265f - r : r;
    return y < 0.0f ? -r : r;
}

#if defined(DAISY_GLSL)
#define atan(y, x) daisyAtan2(y, x)
#else
DAISY_HD float atan(float y, float x) {
    return daisyAtan2(y, x);
}
#endif

DAISY_SHARED_END

#endif  // DAISY_SHARED_PRELUDE_H
