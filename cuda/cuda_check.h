#pragma once
// CUDA_CHECK (STYLE.md rule 7): every CUDA runtime call and launch of daisy_cuda goes through it.
// A failure returns an Error from the enclosing function (which returns Expected<...>) naming the
// call, the decoded error and file:line; the command then exits 2 with that one line. Nothing
// aborts: a missing driver, an out-of-memory device or a failed launch is a message.
#include <cuda_runtime.h>

#include "core/expected.h"
#include "cuda/cuda_error.h"

#define CUDA_CHECK(call)                                                                     \
    do {                                                                                     \
        const cudaError_t daisyCudaError_ = (call);                                          \
        if (daisyCudaError_ != cudaSuccess) {                                                \
            return ::daisy::Error{                                                           \
                ::daisy::cudaErrorMessage(int(daisyCudaError_), #call, __FILE__, __LINE__)}; \
        }                                                                                    \
    } while (0)
