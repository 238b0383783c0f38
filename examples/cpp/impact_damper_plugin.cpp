// The impact damper as a shared library the command line and Python load:
//   vimpact period --model libimpact_damper.so --set d=0.8
//   vimpact.Model.from_file("libimpact_damper.so")
#include <vimpact/model/export.hpp>

#include "impact_damper.hpp"

VIMPACT_EXPORT_MODEL(impact_damper)
