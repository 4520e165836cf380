#pragma once
// The cuda backend's overlap of host and device work (docs/gpu.md), as plain host code so that
// it is tested without a device (tests/cuda/batch_plan_test.cpp). No CUDA types here.
#include <algorithm>
#include <cstddef>

#include "core/expected.h"

namespace daisy {

// The range of chunk `chunk` when `total` items are cut into chunks of `chunkSize` (> 0).
struct ChunkRange {
    std::size_t first = 0;
    std::size_t count = 0;
};
inline std::size_t chunkCount(std::size_t total, std::size_t chunkSize) {
    return (total + chunkSize - 1) / chunkSize;
}
inline ChunkRange chunkRange(std::size_t chunk, std::size_t chunkSize, std::size_t total) {
    const std::size_t first = chunk * chunkSize;
    return {first, std::min(chunkSize, total - first)};
}

// Runs chunks 0 .. count - 1 through two slots. submit(slot, chunk) packs the chunk's input into
// the slot's host buffer and queues its device work on the slot's stream; finish(slot, chunk)
// waits for that work and unpacks its results. Chunk c + 1 is submitted before chunk c is
// finished, so the host packs one chunk while the device runs the other, and a slot is reused
// only after its previous chunk finished. Both return Expected<void>; the first error stops the
// run and is returned (the caller then waits for whatever is still queued).
template <typename Submit, typename Finish>
Expected<void> runDoubleBuffered(std::size_t count, Submit&& submit, Finish&& finish) {
    for (std::size_t c = 0; c < count; ++c) {
        const int slot = int(c % 2);
        if (c >= 2) {
            Expected<void> done = finish(slot, c - 2);
            if (!done) return done;
        }
        Expected<void> started = submit(slot, c);
        if (!started) return started;
    }
    for (std::size_t c = count >= 2 ? count - 2 : 0; c < count; ++c) {
        Expected<void> done = finish(int(c % 2), c);
        if (!done) return done;
    }
    return {};
}

}  // namespace daisy
