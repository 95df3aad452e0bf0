#include "common/bind.hpp"

using namespace bakeshop;

void bind_area(nb::module_& m) {}
