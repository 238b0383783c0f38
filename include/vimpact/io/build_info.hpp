#pragma once
// Facts fixed at build time and recorded in every output file.
#include <string_view>

namespace vimpact {

std::string_view version();
std::string_view git_hash();
std::string_view python_dir();          // the directory that holds the plotting package vimpact/
std::string_view python_module_dir();   // the one that holds it with its compiled module (explore)
std::string_view python_interpreter();  // the interpreter that has numpy and matplotlib
// Where vimpact's and Eigen's headers are, for compiling model files with the library's own
// Runge-Kutta steps inlined (src/model_file_compile.cpp): the installed copy (found relative
// to the loaded library, so a moved install or a Python package finds its own), the source tree.
std::string_view installed_include_dir();
std::string_view source_include_dir();
std::string_view eigen_include_dir();

}  // namespace vimpact
