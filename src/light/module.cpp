// bakeshop.light._native: the kernels of bakeshop.light.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
