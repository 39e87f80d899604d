#pragma once
// The two Simplifier implementations (private; use makeSimplifier).
#include "hlod/Simplifier.h"

namespace hlod {

Simplifier* makeMeshoptSimplifier();
Simplifier* makeOpenMeshSimplifier();

}  // namespace hlod
