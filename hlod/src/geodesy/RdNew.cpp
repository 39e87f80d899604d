// RD New <-> WGS 84 by the approximation formulas of Schreutelkamp and Strang van Hees (2001):
// polynomials in the offsets from Amersfoort, the projection's centre, giving arc seconds
// (RD -> WGS 84) or metres (WGS 84 -> RD); within about a metre over the Netherlands.
#include <array>

#include "hlod/geodesy/Projection.h"

namespace hlod {

namespace {

// Amersfoort: RD (155000, 463000) = 52.15517440 N, 5.38720621 E.
constexpr double kX0 = 155000.0, kY0 = 463000.0;
constexpr double kLat0 = 52.15517440, kLon0 = 5.38720621;

// A term c * a^p * b^q.
struct Term {
  int p, q;
  double c;
};

double sum(const Term* terms, std::size_t n, double a, double b) {
  double s = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    double t = terms[i].c;
    for (int k = 0; k < terms[i].p; ++k) t *= a;
    for (int k = 0; k < terms[i].q; ++k) t *= b;
    s += t;
  }
  return s;
}

// RD -> WGS 84: K_pq (latitude) and L_pq (longitude), arc seconds, in dX = (x - x0) 1e-5 and
// dY = (y - y0) 1e-5.
constexpr std::array<Term, 11> kK{{{0, 1, 3235.65389},
                                   {2, 0, -32.58297},
                                   {0, 2, -0.24750},
                                   {2, 1, -0.84978},
                                   {0, 3, -0.06550},
                                   {2, 2, -0.01709},
                                   {1, 0, -0.00738},
                                   {4, 0, 0.00530},
                                   {2, 3, -0.00039},
                                   {4, 1, 0.00033},
                                   {1, 1, -0.00012}}};
constexpr std::array<Term, 12> kL{{{1, 0, 5260.52916},
                                   {1, 1, 105.94684},
                                   {1, 2, 2.45656},
                                   {3, 0, -0.81885},
                                   {1, 3, 0.05594},
                                   {3, 1, -0.05607},
                                   {0, 1, 0.01199},
                                   {3, 2, -0.00256},
                                   {1, 4, 0.00128},
                                   {0, 2, 0.00022},
                                   {2, 0, -0.00022},
                                   {5, 0, 0.00026}}};
// WGS 84 -> RD: R_pq (x) and S_pq (y), metres, in dPhi = 0.36 (lat - lat0) and
// dLam = 0.36 (lon - lon0) (degrees to units of 10,000 arc seconds).
constexpr std::array<Term, 9> kR{{{0, 1, 190094.945},
                                  {1, 1, -11832.228},
                                  {2, 1, -114.221},
                                  {0, 3, -32.391},
                                  {1, 0, -0.705},
                                  {3, 1, -2.340},
                                  {1, 3, -0.608},
                                  {0, 2, -0.008},
                                  {2, 3, 0.148}}};
constexpr std::array<Term, 10> kS{{{1, 0, 309056.544},
                                   {0, 2, 3638.893},
                                   {2, 0, 73.077},
                                   {1, 2, -157.984},
                                   {3, 0, 59.788},
                                   {0, 1, 0.433},
                                   {2, 2, -6.439},
                                   {1, 1, -0.032},
                                   {0, 4, 0.092},
                                   {1, 4, -0.054}}};

}  // namespace

LatLon rdNewToWgs84(const glm::dvec2& rd) {
  const double dx = (rd.x - kX0) * 1e-5, dy = (rd.y - kY0) * 1e-5;
  return {kLat0 + sum(kK.data(), kK.size(), dx, dy) / 3600.0,
          kLon0 + sum(kL.data(), kL.size(), dx, dy) / 3600.0, 0.0};
}

glm::dvec2 wgs84ToRdNew(const LatLon& p) {
  const double dPhi = 0.36 * (p.lat - kLat0), dLam = 0.36 * (p.lon - kLon0);
  return {kX0 + sum(kR.data(), kR.size(), dPhi, dLam), kY0 + sum(kS.data(), kS.size(), dPhi, dLam)};
}

}  // namespace hlod
