#pragma once
// The reference: every visible leaf. A leaf that is not resident is replaced by its nearest
// resident ancestor (with the group rule: a node is refined only when all its visible children
// are resident, since a parent covers all its children).
#include "hlod/runtime/Selector.h"

namespace hlod {

class FullSelector final : public Selector {
 public:
  FullSelector(const Skeleton& skeleton, const SelectorParams& params = {});
  std::string_view name() const override { return "full"; }
  Selection select(const View& view, const Residency& residency) override;
};

}  // namespace hlod
