// What every binding file shares: numpy arrays as nanobind ndarrays. Inputs (`In`) are
// read-only and may be converted (a copy when the dtype or order differs); outputs (`Out`) are
// written in place, so they must be bound with `.noconvert()` (a copy would drop the writes):
//   m.def("f", &f, "src"_a, "out"_a.noconvert(), nb::call_guard<nb::gil_scoped_release>());
// Every kernel releases the GIL (the call guard) and checks the shapes it is given before it
// touches memory (`require`).
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <initializer_list>
#include <string>

#include "common/kernel.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace bakeshop {

template <class T, size_t N>
using In = nb::ndarray<const T, nb::numpy, nb::ndim<N>, nb::c_contig, nb::device::cpu>;
template <class T, size_t N>
using Out = nb::ndarray<T, nb::numpy, nb::ndim<N>, nb::c_contig, nb::device::cpu>;

// A ValueError unless `ok`: the binding's check of the shapes it was given.
inline void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

using release_gil = nb::call_guard<nb::gil_scoped_release>;

// Whether array `a`'s leading dimensions are `dims`: require(shape_is(out, {h, w, 3}), "...").
template <class A>
bool shape_is(const A& a, std::initializer_list<size_t> dims) {
  size_t i = 0;
  for (size_t d : dims)
    if (a.shape(i++) != d) return false;
  return true;
}

}  // namespace bakeshop
