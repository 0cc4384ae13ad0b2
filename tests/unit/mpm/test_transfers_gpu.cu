// The transfer tests compiled as CUDA, so that the kernels exist for the GPU backend
// (run with --device=cuda; CTest label gpu).
#include "test_transfers.cpp"
