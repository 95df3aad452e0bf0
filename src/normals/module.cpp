// bakeshop.normals._native: the kernels of bakeshop.normals.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
