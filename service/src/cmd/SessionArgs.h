#pragma once
// What a session of a node store takes from the command line, for one frame (`hlodr render
// STORE`) and for a path (`hlodr render STORE --path`): --size, --budget-ms, --memory-mb,
// --selector, --params, --splats, --occlusion, --gpu-mb and --show-occlusion, by the settings
// table.
#include "service/Args.h"
#include "service/Session.h"

namespace service::cmd {

// An Error names the option and its range (a usage error).
hlod::Result<SessionOptions> sessionFromArgs(const Args& args);

}  // namespace service::cmd
