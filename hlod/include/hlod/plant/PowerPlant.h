#pragma once
// A procedural power plant (`hlodr plant`): the kind of CAD scene Manocha's paper renders (the
// Power Plant, 13 M polygons in 1,200 objects; the Double Eagle tanker, 82 M in 127 k), made of
// many objects organised by function, as a glTF scene any viewer opens. Metres, Y up.
//
// The site is a grid of units, each a boiler in a steel frame with three levels of walkways
// (grating, railings, a stair tower), a tank yard with horizontal tanks on saddles, and branch
// pipes from the pipe rack into the boiler and the tanks. After each row of units a pipe rack
// runs the site's width: portal frames every 6 m with two tiers of pipes and a catwalk at 7 m
// between them, joined to each unit's first level by a bridge, so the 7 m level is one network of
// catwalks. The long pipe runs lie on the racks and snake from rack to rack at the site's ends
// (elbows), spanning the whole site as single large objects, with flanges every 12 m; valves sit
// on runs and branches, bolts on every flange (small objects), shoes under the pipes on every
// portal. Parts repeated as they are (bolts, valves, shoes, beams, stairs, boilers) are meshes
// instanced by nodes; pipes, tanks, railings and the ground are meshes of their own. Flat
// materials, one per part type. Everything comes from the seed: the same options give the same
// bytes.
#include <cstdint>
#include <map>
#include <string>

#include "hlod/Mesh.h"
#include "hlod/plant/GlbWriter.h"

namespace hlod {

struct PlantOptions {
  // About how many objects (nodes with a mesh): the unit count follows from it (about 2,000
  // objects a unit; at least one unit).
  std::uint64_t objects = 20000;
  std::uint64_t seed = 1;
  // Tessellation: segments around pipes and along bends scale with it, in (0, 4].
  double detail = 1.0;
};

// Limits PlantOptions::objects is checked against (the CLI's).
constexpr std::uint64_t kMinPlantObjects = 1;
constexpr std::uint64_t kMaxPlantObjects = 1'000'000;

struct PlantSummary {
  std::size_t units = 0, racks = 0, pipeRuns = 0;
  std::uint64_t objects = 0, triangles = 0;  // flattened: every instance counted
  // Per part type (its material's name): objects and triangles.
  std::map<std::string, std::pair<std::uint64_t, std::uint64_t>> byType;
  Aabb bounds;
};

struct Plant {
  GltfScene scene;
  PlantSummary summary;
};

// The plant for the options (asserted within their limits: detail in (0, 4], objects in
// [kMinPlantObjects, kMaxPlantObjects]).
Plant makePowerPlant(const PlantOptions& options);

}  // namespace hlod
