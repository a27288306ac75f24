#include "vpsim/planners/planner.h"

namespace vpsim::planners {}  // namespace vpsim::planners
