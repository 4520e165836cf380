#include "cuda/cuda_error.h"

#include <cuda_runtime.h>

#include <cstring>

#include "core/strings.h"

namespace daisy {

std::string cudaErrorMessage(int code, const char* call, const char* file, int line) {
    const cudaError_t error = static_cast<cudaError_t>(code);
    const char* name = cudaGetErrorName(error);
    const char* text = cudaGetErrorString(error);
    // The last "/cuda/" of the path: the source tree's own folder, whatever the checkout is named.
    const char* shortFile = file;
    for (const char* p = std::strstr(file, "/cuda/"); p; p = std::strstr(p + 1, "/cuda/"))
        shortFile = p + 1;
    return concat("cuda: ", call, " failed: ", name ? name : "unknown error", " (",
                  text ? text : "no description", ") at ", shortFile, ":", line);
}

}  // namespace daisy
