#include "common/bind.hpp"

using namespace bakeshop;

void bind_sampling(nb::module_& m) {}
