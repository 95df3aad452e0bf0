// bakeshop.image._native: the kernels of bakeshop.image.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
