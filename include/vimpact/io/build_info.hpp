#pragma once
// Facts fixed at build time and recorded in every output file.
#include <string_view>

namespace vimpact {

std::string_view version();
std::string_view git_hash();
std::string_view python_dir();          // the plotting package (python/vimpact)
std::string_view python_interpreter();  // the interpreter that has numpy and matplotlib

}  // namespace vimpact
