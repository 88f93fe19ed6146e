// Body: a shared, immutable implicit function, the handle CSG trees and transforms hold.
#pragma once

#include <memory>

#include "hexmesh/core/implicit_function.h"

namespace hexmesh {

using Body = std::shared_ptr<const ImplicitFunction>;

}  // namespace hexmesh
