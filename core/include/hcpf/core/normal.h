#pragma once
// Fast standard-normal variates on top of hcpf::Rng's 64-bit output.
//
// Ziggurat method (Marsaglia & Tsang, "The Ziggurat Method for Generating
// Random Variables", J. Stat. Software 5(8), 2000) with 256 layers: one 64-bit
// draw per variate ~99% of the time (8 bits pick the layer, 1 bit the sign, the
// top 53 bits the uniform), exact rejection otherwise, Marsaglia's exponential
// method for the tail beyond r = 3.6541528853610088. The variates are exactly
// N(0, 1) distributed (up to 53-bit uniforms), not an approximation.
//
// Deterministic: the same Rng state gives the same numbers on every platform
// that computes the layer tables the same way (IEEE double, glibc libm).
// Rng::Normal() (Box–Muller) remains the project's reference generator; the
// tracker (particle noise) and the renderer (sensor noise) use this one,
// because the Gaussian draws dominate their loops.
//
// Thread-safety: the layer tables are built once at static initialisation and
// only read afterwards; each call touches only the Rng it is given.

#include <span>

#include "hcpf/core/rng.h"

namespace hcpf {

// One N(0, 1) variate.
double ZigguratNormal(Rng& rng);

// Fills `out` with independent N(0, 1) variates; identical to calling
// ZigguratNormal out.size() times in order.
void FillStandardNormal(Rng& rng, std::span<double> out);

}  // namespace hcpf
