#pragma once
// The message of a failed CUDA runtime call (STYLE.md rule 7: CUDA_CHECK, cuda/cuda_check.h), in a
// header without cuda_runtime.h so that tests and callers outside cuda/ can use it.
#include <string>

namespace daisy {

// "cuda: <call> failed: <cudaErrorName> (<cudaGetErrorString>) at <file>:<line>" for the
// cudaError_t `code` (an int here); `file` is shortened to the part from its last "/cuda/" on.
std::string cudaErrorMessage(int code, const char* call, const char* file, int line);

}  // namespace daisy
