#include "core/parallel.h"

#include <thread>

namespace robophi::detail {

int availableThreads() {
#ifdef _OPENMP
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#else
  return 1;  // built without OpenMP: the loops run serially whatever the count
#endif
}

}  // namespace robophi::detail
