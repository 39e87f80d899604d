// EPSG codes of reference-system strings and their kinds (hlod/geodesy/Epsg.h).
#include "hlod/geodesy/Epsg.h"

#include <algorithm>
#include <cctype>

namespace hlod {

int epsgFromReference(std::string_view reference) {
  // The code is the digits after the last "EPSG" marker, past its version ("/0/") or empty
  // version ("::") field.
  std::string upper(reference);
  std::transform(upper.begin(), upper.end(), upper.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const std::size_t at = upper.rfind("EPSG");
  if (at == std::string::npos) return 0;
  std::size_t i = upper.size();
  while (i > at && std::isdigit(static_cast<unsigned char>(upper[i - 1]))) --i;
  if (i == upper.size() || upper.size() - i > 6) return 0;
  // Between the marker and the digits only separators and a version number may stand.
  for (std::size_t k = at + 4; k < i; ++k)
    if (upper[k] != ':' && upper[k] != '/' && upper[k] != '0' && upper[k] != '.') return 0;
  return std::stoi(upper.substr(i));
}

CrsKind crsKind(int epsg) {
  switch (epsg) {
    case 4326:
    case 4979:
    case 4258:
    case 4937:
    case 4269:
    case 4283:
    case 7844:
    case 4167:
    case 4612:
    case 6668:
    case 4490:
      return CrsKind::Geographic;
    case 4978:
    case 4936:
    case 7789:
      return CrsKind::Geocentric;
    default:
      return CrsKind::Projected;
  }
}

std::string describeEpsg(int epsg) {
  if (epsg <= 0) return "none declared";
  const char* kind = crsKind(epsg) == CrsKind::Geographic   ? "geographic"
                     : crsKind(epsg) == CrsKind::Geocentric ? "geocentric (ECEF)"
                                                            : "projected";
  return "EPSG:" + std::to_string(epsg) + " (" + kind + ")";
}

}  // namespace hlod
