#pragma once
// Dividing a block among its facades (Parry et al. sec. 3, Fig. 3: the block's first-level
// children are its facades), for the parry simplifier's stores. Below the facades the builder
// divides pieces into slabs as for the others (SlabPartition.h).
#include <cstddef>

#include "builder/SlabPartition.h"
#include "hlod/UpAxis.h"

namespace hlod {

// One part per facade (hlod/parry/Faces.h: the block's sides, roof and underside) in facade
// order, axis -1 and no planes. A facade of fewer than minTriangles triangles joins the facade
// whose triangles' mean centroid is nearest its own (so a child is never a crumb); a block of
// one facade is one part.
SlabPartition partitionIntoFacades(const Mesh& mesh, UpAxis up, std::size_t minTriangles);

}  // namespace hlod
