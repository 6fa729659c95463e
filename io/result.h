#pragma once
/// io/ reports errors with the project's one Result/Error type (sim/core/result.h).

#include "sim/core/result.h"

namespace atelier::io {
using atelier::Error;
using atelier::Result;
} // namespace atelier::io
