#pragma once
// `hlodr info`'s figures for the criteria of Manocha sec. 2.1.1 (hlod/builder/HierarchyCriteria.h):
// for a model, its object hierarchy and its plane cuts side by side, as `hlodr build` would make
// them with the default options; for a store, its tree.
#include <nlohmann/json.hpp>

#include "hlod/Mesh.h"
#include "hlod/store/Skeleton.h"

namespace service::cmd {

// The figures as JSON ({"objects": {...}, "planes": {...}, "stages": {...}}), and printed as a
// table when print is true.
nlohmann::json modelHierarchyInfo(const hlod::Model& model, bool print);
// The figures of a store's tree (localisation by objects is not known to a store: its objects'
// figures are left out).
nlohmann::json storeHierarchyInfo(const hlod::Skeleton& skeleton, bool print);

}  // namespace service::cmd
