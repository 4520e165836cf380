// Counter-based randomness for the shared kernels: stateless hashes of (seed, index), so every
// backend draws the same numbers for the same patch pair and sample index, in any thread order.
#ifndef DAISY_SHARED_RNG_H
#define DAISY_SHARED_RNG_H

#include "prelude.h"

DAISY_SHARED_BEGIN

// PCG-based 32-bit hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT 9(3),
// "pcg"): one LCG step then the RXS-M-XS output permutation. A bijection on uint.
DAISY_HD uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Seed of the unordered patch pair {i, j}: hash(min(i, j), max(i, j), seed) (DESIGN.md section 3),
// so (i, j) and (j, i) draw the same sample points.
DAISY_HD uint pairSeed(uint i, uint j, uint seed) {
    uint lo = min(i, j);
    uint hi = max(i, j);
    return pcgHash(pcgHash(pcgHash(seed) ^ lo) + hi);
}

// Seed of one patch's own stream (the stochastic method's rays leaving patch i). Disjoint in
// construction from pairSeed by an extra hash round.
DAISY_HD uint patchSeed(uint i, uint seed) {
    return pcgHash(pcgHash(pcgHash(seed) + 0x9e3779b9u) ^ i);
}

// Seed for a sub-stream `stream` of `seed` (e.g. 0 = points on the first patch, 1 = the second).
DAISY_HD uint streamSeed(uint seed, uint stream) {
    return pcgHash(seed ^ pcgHash(stream + 1u));
}

// Uniform float in [0, 1) from the top 24 bits of x: exactly representable, never 1.
DAISY_HD float uintToUnitFloat(uint x) {
    return float(x >> 8u) * (1.0f / 16777216.0f);
}

// Uniform float in [0, 1) for (index, seed): an independent hash per index.
DAISY_HD float hashToUnitFloat(uint index, uint seed) {
    return uintToUnitFloat(pcgHash(index ^ pcgHash(seed)));
}

// Pseudo-random permutation of [0, l): returns the image of i < l under the permutation chosen by
// p (Kensler 2013, "Correlated Multi-Jittered Sampling", Pixar TM 13-01, permute(): a hash that is
// a bijection on the next power of two, cycle-walked into [0, l)). l >= 1.
DAISY_HD uint permuteIndex(uint i, uint l, uint p) {
    uint w = l - 1u;
    w |= w >> 1u;
    w |= w >> 2u;
    w |= w >> 4u;
    w |= w >> 8u;
    w |= w >> 16u;
    do {
        i ^= p;
        i *= 0xe170893du;
        i ^= p >> 16u;
        i ^= (i & w) >> 4u;
        i ^= p >> 8u;
        i *= 0x0929eb3fu;
        i ^= p >> 23u;
        i ^= (i & w) >> 1u;
        i *= 1u | p >> 27u;
        i *= 0x6935fa69u;
        i ^= (i & w) >> 11u;
        i *= 0x74dcb303u;
        i ^= (i & w) >> 2u;
        i *= 0x9e501cc3u;
        i ^= (i & w) >> 2u;
        i *= 0xc860a3dfu;
        i &= w;
        i ^= i >> 5u;
    } while (i >= l);
    return (i + p) % l;
}

// Kensler 2013's randfloat(): a well-mixed float in [0, 1) for (i, p).
DAISY_HD float kenslerRandFloat(uint i, uint p) {
    i ^= p;
    i ^= i >> 17u;
    i ^= i >> 10u;
    i *= 0xb36534e5u;
    i ^= i >> 12u;
    i ^= i >> 21u;
    i *= 0x93fc4795u;
    i ^= 0xdf6e307fu;
    i ^= i >> 17u;
    i *= 1u | p >> 18u;
    return uintToUnitFloat(i);
}

DAISY_SHARED_END

#endif  // DAISY_SHARED_RNG_H
