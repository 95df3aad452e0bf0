// bakeshop._native: the OpenMP thread count of the calling thread (bakeshop.threads).
#include <omp.h>

#include "common/bind.hpp"

NB_MODULE(_native, m) {
  m.def("get_threads", []() { return omp_get_max_threads(); },
        "The threads the calling thread's parallel loops use.");
  m.def("set_threads", [](int n) {
          bakeshop::require(n >= 1, "the thread count must be at least 1");
          omp_set_num_threads(n);
        }, "n"_a, "Set the threads the calling thread's parallel loops use.");
  m.def("cpus", []() { return omp_get_num_procs(); },
        "The processors this process may use.");
}
