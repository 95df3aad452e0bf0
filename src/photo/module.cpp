// bakeshop.photo._native: the kernels of bakeshop.photo.
#include "common/bind.hpp"

using namespace bakeshop;

NB_MODULE(_native, m) {}
