// CityJSON: the input is the whole file, read as model.city.json (any version; the seeds cover
// 0.x semantics arrays, 2.0 solids with semantics and materials, templates and a WGS 84 CRS).
#include "ImportFuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::importAndCheck("city.json", fuzz::view(data, size));
  return 0;
}
