# C++20 for CUDA sources. CMake 3.25 (Debian 12) predates nvcc's C++20 support in its
# compiler tables, so CUDA_STANDARD 20 (or cxx_std_20 reaching a CUDA source) fails with
# "does not support this"; teach it the flag nvcc 12+ takes.
if(NOT DEFINED CMAKE_CUDA20_STANDARD_COMPILE_OPTION)
  set(CMAKE_CUDA20_STANDARD_COMPILE_OPTION "-std=c++20")
  set(CMAKE_CUDA20_EXTENSION_COMPILE_OPTION "-std=c++20")
  list(APPEND CMAKE_CUDA_COMPILE_FEATURES cuda_std_20)
  set(CMAKE_CUDA20_COMPILE_FEATURES cuda_std_20)
endif()
set(CMAKE_CUDA_STANDARD 20)
set(CMAKE_CUDA_STANDARD_REQUIRED ON)
