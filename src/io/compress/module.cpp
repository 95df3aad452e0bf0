// bakeshop.io.compress._native: the kernels of bakeshop.io.compress.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
