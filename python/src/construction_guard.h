#pragma once
// pybind11 lets Python make an instance of any bound class without constructing its C++
// object (`Cls.__new__(Cls)`, also what copy and pickle do), and using that instance crashed
// the interpreter. guard_construction makes that impossible for every class of a module.
#include <pybind11/pybind11.h>

namespace fabkit::python {

/// For every class bound in `m` and its submodules: a class without a Python constructor
/// refuses `__new__` with a TypeError naming how to get one; a class with one builds its C++
/// object in `__new__` already (its `__init__` then does nothing), so no instance ever exists
/// without it.
void guard_construction(pybind11::module_ m);

}  // namespace fabkit::python
