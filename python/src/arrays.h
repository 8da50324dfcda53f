#pragma once
// numpy in, numpy out: reading array arguments, the shape checks and the batched loop every
// binding uses.
//
// An array argument arrives as the caller gave it (ArrayArg: an ndarray or anything numpy makes
// one of) and is read as a C-contiguous array of the element type the C++ call consumes (float for
// variates and table coordinates, double for directions): a copy when its dtype, byte order or
// layout differ (Fortran order, a slice with a step), never a reinterpretation. What is not real
// numbers (bool, complex, text, objects) or not of the expected shape raises ValueError naming
// the argument and the shape. A batch of n rows runs as one C++ loop; from kParallelRows rows on,
// the loop releases the GIL and runs on oneTBB's threads (each row is independent and the C++
// calls are const and thread-safe, so the result does not depend on the number of threads).

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "acdf/sampling/rgb.h"
#include "acdf/sampling/sphere.h"

namespace acdf::python {

namespace py = pybind11;

template <class T>
using Array = py::array_t<T, py::array::c_style | py::array::forcecast>;

// An array argument as given; numbers() and batch() read it.
struct ArrayArg {
  py::object value;
};

}  // namespace acdf::python

namespace pybind11::detail {
// Every object binds to an ArrayArg (None only where the argument is optional), so that what it
// holds is judged by numbers() with the argument's name, not by overload resolution's TypeError.
template <>
struct type_caster<acdf::python::ArrayArg> {
  PYBIND11_TYPE_CASTER(acdf::python::ArrayArg, const_name("numpy.ndarray"));
  bool load(handle source, bool) {
    if (source.is_none()) return false;
    value.value = reinterpret_borrow<object>(source);
    return true;
  }
};
}  // namespace pybind11::detail

namespace acdf::python {

inline constexpr std::size_t kParallelRows = 8192;

inline std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

inline std::string rowShape(std::size_t columns) {
  return columns == 0 ? "(n,)" : "(n, " + std::to_string(columns) + ")";
}

// The argument `name` as a C-contiguous array of T (see the top of this file); `shape` is what
// the error message says is expected, e.g. "of shape (n, 2)".
template <class T>
Array<T> numbers(const ArrayArg& arg, const char* name, const std::string& shape) {
  const std::string expected = std::string(name) + ": expected real numbers " + shape;
  const py::array a = py::array::ensure(arg.value);  // a list, a scalar: numpy's array of it
  if (!a)
    throw py::value_error(expected + ", got " + py::str(py::type::of(arg.value).attr("__name__")).cast<std::string>());
  const char kind = a.dtype().kind();
  if (kind == 'f' || kind == 'i' || kind == 'u')
    if (Array<T> out = Array<T>::ensure(a)) return out;
  throw py::value_error(expected + ", got dtype " + py::str(a.dtype()).cast<std::string>());
}

// The number of rows of `a`, which must have shape (n, columns), or (n,) when columns == 0.
// A single row may also be given as shape (columns,) when allowSingle (it counts as n = 1).
inline std::size_t rows(const py::array& a, std::size_t columns, const char* name, bool allowSingle = false) {
  if (columns == 0) {
    if (a.ndim() != 1) throw py::value_error(std::string(name) + ": expected shape (n,), got " + shapeText(a));
    return static_cast<std::size_t>(a.shape(0));
  }
  if (allowSingle && a.ndim() == 1 && static_cast<std::size_t>(a.shape(0)) == columns) return 1;
  if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(1)) != columns)
    throw py::value_error(std::string(name) + ": expected shape (n, " + std::to_string(columns) + "), got " +
                          shapeText(a));
  return static_cast<std::size_t>(a.shape(0));
}

// A batch argument read by numbers(): `rows` rows of `columns` values (shape (n, columns), or (n,)
// when columns == 0; one row may be given as (columns,) when allowSingle, counting as n = 1).
// `data` points into `array`, which owns the values, so it can be read without the GIL.
template <class T>
struct Batch {
  Array<T> array;
  const T* data;
  std::size_t rows;
};

template <class T>
Batch<T> batch(const ArrayArg& arg, std::size_t columns, const char* name, bool allowSingle = false) {
  Array<T> a = numbers<T>(arg, name, "of shape " + rowShape(columns));
  const std::size_t n = rows(a, columns, name, allowSingle);
  const T* data = a.data();
  return {std::move(a), data, n};
}

// Two batches that go together row by row: the same n, or one of them a single row broadcast
// over the other's (e.g. one ωo for n ωi). Returns n.
inline std::size_t pairedRows(std::size_t a, std::size_t b, const char* names) {
  if (a == b || b == 1) return a;
  if (a == 1) return b;
  throw py::value_error(std::string(names) + ": row counts differ (" + std::to_string(a) + " and " + std::to_string(b) +
                        ")");
}

// An output array of shape (n,) or (n, columns).
template <class T>
py::array_t<T> output(std::size_t n, std::size_t columns = 0) {
  if (columns == 0) return py::array_t<T>({static_cast<py::ssize_t>(n)});
  return py::array_t<T>({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(columns)});
}

// body(i) for i in [0, n): serially for small batches, else without the GIL on oneTBB's threads.
// body must not touch Python objects (take raw pointers before the call).
template <class Body>
void forEachRow(std::size_t n, const Body& body) {
  if (n < kParallelRows) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  py::gil_scoped_release release;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) body(i);
  });
}

// Row i of an (n, 3) double array, or its only row when it holds one (broadcast).
inline Vec3d vec3At(const double* data, std::size_t rowsInArray, std::size_t i) {
  const double* v = data + 3 * (rowsInArray == 1 ? 0 : i);
  return {v[0], v[1], v[2]};
}

// Directions must be finite and non-zero; they need not be unit length (direction() normalises).
inline void requireDirections(const double* data, std::size_t n, const char* name) {
  for (std::size_t i = 0; i < n; ++i) {
    const double x = data[3 * i], y = data[3 * i + 1], z = data[3 * i + 2];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || (x == 0 && y == 0 && z == 0))
      throw py::value_error(std::string(name) + ": row " + std::to_string(i) + " is not a finite non-zero vector");
  }
}

// Row i of a direction array (requireDirections checked it), as a unit vector. Rows already of
// unit length to 1e-12 are taken as they are, so C++ and Python see the same bits.
inline Vec3d direction(const double* data, std::size_t rowsInArray, std::size_t i) {
  const Vec3d v = vec3At(data, rowsInArray, i);
  const double squared = dot(v, v);
  return std::abs(squared - 1.0) <= 1e-12 ? v : v * (1.0 / std::sqrt(squared));
}

// A batch of directions: shape (n, 3), or (3,) for one direction that broadcasts.
struct Directions {
  Batch<double> values;
  Vec3d operator[](std::size_t i) const { return direction(values.data, values.rows, i); }
  std::size_t rows() const { return values.rows; }
};

inline Directions directions(const ArrayArg& a, const char* name) {
  Batch<double> b = batch<double>(a, 3, name, true);
  requireDirections(b.data, b.rows, name);
  return {std::move(b)};
}

inline void storeRgb(float* data, std::size_t i, const Rgb& c) {
  data[3 * i] = c.r;
  data[3 * i + 1] = c.g;
  data[3 * i + 2] = c.b;
}

inline void storeVec3(double* data, std::size_t i, const Vec3d& v) {
  data[3 * i] = v.x;
  data[3 * i + 1] = v.y;
  data[3 * i + 2] = v.z;
}

}  // namespace acdf::python
