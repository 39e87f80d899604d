#pragma once
// Private: the backend constructors behind createContext, and the shared start-up check.
#include <memory>
#include <string>

#include "renderer/GlContext.h"

namespace renderer {

hlod::Result<std::unique_ptr<GlContext>> createEglContext();
hlod::Result<std::unique_ptr<GlContext>> createOsMesaContext();

// Loads the GL entry points of a current context, fills its info, and checks that it is a
// GL 4.5 core context (glClipControl is needed for reversed-Z).
hlod::Status initialiseContext(GlContext& context, std::string backend, std::string skipped);

}  // namespace renderer
