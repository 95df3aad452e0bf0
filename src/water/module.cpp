// bakeshop.water._native: the kernels of bakeshop.water.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
