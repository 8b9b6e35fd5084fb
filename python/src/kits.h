#pragma once
// Each kit's bindings, in python/src/<kit>_bindings.cpp, into its own submodule of _fabkit.
#include <pybind11/pybind11.h>

namespace fabkit::python {

void bind_hacks(pybind11::module_ m);
void bind_flatpack(pybind11::module_ m);
void bind_rods(pybind11::module_ m);
void bind_templates(pybind11::module_ m);

}  // namespace fabkit::python
