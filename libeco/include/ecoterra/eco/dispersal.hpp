#pragma once
// Seed production and dispersal.
//   seeds per year  N = STR (D_cm / 30)^2 * vigor   (SORTIE-ND's normalisation by a 30 cm parent,
//                   Ribbens et al. 1994, with exponent 2: seed output ~ basal area; vigor = the
//                   plant's mean growth percentage over the year's leaf-on days)
//   distance        two-part exponential K(d) = (1-ks)/a1 e^(-d/a1) + ks/a2 e^(-d/a2)
//                   (Lischke & Loeffler 2006, iLand), direction uniform
// A seed establishes only where the species' germination needs are met (light at the ground,
// relative soil water, no standing water) and then with probability p_germ * f_texture * f_pH.
#include "ecoterra/eco/species.hpp"
#include "ecoterra/random.hpp"

namespace ecoterra::eco {

double seeds_per_year(const Species& s, double dbh_m, double vigor);
double sample_dispersal_distance(const DispersalKernel& k, Rng& rng);
/// Poisson draw (Knuth's product method below a mean of 30, a rounded normal above).
std::int64_t poisson(Rng& rng, double mean);

} // namespace ecoterra::eco
