// bakeshop.buoyancy._native: the kernels of bakeshop.buoyancy.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
