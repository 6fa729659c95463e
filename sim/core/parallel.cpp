#include "sim/core/parallel.h"

#if defined(ATELIER_HAVE_OPENMP)
#include <omp.h>
#endif

namespace atelier::sim {

namespace {
#if defined(ATELIER_HAVE_OPENMP)
const int DEFAULT_THREADS = omp_get_max_threads();
#endif
} // namespace

int threadCount() {
#if defined(ATELIER_HAVE_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}

void setThreadCount(int n) {
#if defined(ATELIER_HAVE_OPENMP)
    omp_set_num_threads(n < 1 ? DEFAULT_THREADS : n);
#else
    (void)n;
#endif
}

} // namespace atelier::sim
