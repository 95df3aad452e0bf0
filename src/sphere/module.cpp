// bakeshop.sphere._native: the kernels of bakeshop.sphere (the sampling ones, then the area and
// matrix ones).
#include "common/bind.hpp"

void bind_sampling(nb::module_& m);
void bind_area(nb::module_& m);

NB_MODULE(_native, m) {
  bind_sampling(m);
  bind_area(m);
}
