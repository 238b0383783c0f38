#pragma once
// The dimension command: correlation dimension of section points of a run, or of a CSV file.
#include "command.hpp"

namespace vimpact::cli {

cli_command add_dimension_command(CLI::App& app);

}  // namespace vimpact::cli
