#pragma once
// `hlodr info`'s figures for a store's view-dependent section (vdr.bin, `hlodr build --vdr`): the
// cluster hierarchy of Manocha sec. 3.1 with each cluster's error ratio and error range, as Yoon
// et al. 2003 define them (hlod/vdr/ClusterHierarchy.h).
#include <nlohmann/json.hpp>

#include "hlod/Result.h"
#include "hlod/store/NodeStore.h"

namespace service::cmd {

// Null for a store without the section. Each object is decoded (and checked) in turn; the JSON
// lists every cluster's depth, vertices, error ratio and error range per object, and the
// printed table gives their spreads, overall and per cluster depth. An object that does not
// decode is an Error.
hlod::Result<nlohmann::json> vdrInfo(const hlod::NodeStore& store, bool print);

}  // namespace service::cmd
