// Per-sample random numbers: a hash chain seeds a 32-bit state per (pixel, sample, seed), and the PCG
// RXS-M-XS output permutation turns each state of a 32-bit LCG into a float in [0, 1). GLSL only (inout).
#ifndef FH_RNG_GLSL
#define FH_RNG_GLSL

// PCG hash (O'Neill 2014's RXS-M-XS on one LCG step), recommended by Jarzynski & Olano 2020,
// "Hash Functions for GPU Rendering" (JCGT 9(3)), as the best quality/speed trade-off for 1D -> 1D.
uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Initial state for one pixel sample: a chain of hashes (each input perturbs the state that the next
// hash scrambles), so neighbouring pixels, consecutive sample indices and seeds give unrelated streams.
uint init_rng(uint pixel, uint sample_index, uint seed) {
    return pcg_hash(pcg_hash(pcg_hash(seed) ^ pixel) + sample_index);
}

// Next uniform float in [0, 1): advance the 32-bit LCG (PCG's 32-bit constants, as in pcg_hash)
// and permute the old state (PCG RXS-M-XS). The top 24 bits times 2^-24 are exact in float, so the largest
// value is 1 - 2^-24 and 1.0 is never returned.
float next_float(inout uint state) {
    uint old = state;
    state = old * 747796405u + 2891336453u;
    uint word = ((old >> ((old >> 28u) + 4u)) ^ old) * 277803737u;
    word = (word >> 22u) ^ word;
    return float(word >> 8u) * (1.0f / 16777216.0f);
}

#endif
