// Owen-scrambled Sobol' points in one and two dimensions (Burley 2020, "Practical Hash-based Owen Scrambling", JCGT
// 9(4)): the stratified, low-discrepancy sampler (`--sampler sobol`). Shared GLSL/C++ subset.
//
// A pixel's sample i draws each of its 2D (or 1D) dimensions from the first two (one) Sobol' dimensions at a shuffled
// index:
//   x_k = owen(sobol_k(owen(i, seed)), hash(seed, k))       k = 0, 1
// Shuffling the index (a nested uniform scramble of its bits, Owen 1995 as hashed by Laine & Karras 2011) gives every
// dimension its own random order, so dimensions are independent of each other (padding, Kollig & Keller 2002) while
// each one's points stay a (0, m, 2)-net (2D) or (0, m, 1)-net (1D) for any power-of-two prefix of the samples; the
// scramble of the values makes every point uniform, so estimates are unbiased. Seeds hash the pixel, the render seed
// and the dimension, so pixels, seeds and dimensions decorrelate; the same (pixel, sample, seed) gives the same point
// (deterministic, resumable, independent of the wave size).
//
// No loop and no table: Sobol' dimension 0 is the bit reversal of the index (van der Corput), and dimension 1's
// generator matrix is Pascal's triangle mod 2, so its point is the reversal of the index's superset-XOR transform (bit
// k of it is the XOR of the index's bits n whose binary digits contain k's: Lucas' theorem), five shift-XOR steps.
#ifndef FH_SOBOL_GLSL
#define FH_SOBOL_GLSL

#ifdef __cplusplus
inline uint bitfieldReverse(uint x) { return glm::bitfieldReverse(x); }
#endif

// Laine & Karras 2011's hash of the bits above each bit (Burley 2020 listing 3, with its improved constants): a random
// permutation of x's value that depends on its low bits only through the bits below (a nested uniform scramble of the
// reversed bits).
uint laine_karras_permutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// Owen's nested uniform scramble of x's 32 bits, each bit flipped by a hash of the bits above it.
uint nested_uniform_scramble(uint x, uint seed) {
    return bitfieldReverse(laine_karras_permutation(bitfieldReverse(x), seed));
}

// Sobol' dimension 1 of point `index` before its bit reversal: bit k is the XOR of the index's bits n with k's binary
// digits among n's (the superset-XOR, or zeta, transform over the five bit positions of k).
uint sobol_dimension_1_reversed(uint index) {
    uint z = index;
    z ^= (z >> 1u) & 0x55555555u;
    z ^= (z >> 2u) & 0x33333333u;
    z ^= (z >> 4u) & 0x0f0f0f0fu;
    z ^= (z >> 8u) & 0x00ff00ffu;
    z ^= (z >> 16u) & 0x0000ffffu;
    return z;
}

// A hash of two words (the PCG output permutation over a multiply-xorshift mix): seeds per pixel and dimension.
uint hash_combine(uint a, uint b) {
    uint state = (a ^ (b * 0x9e3779b9u + 0x7f4a7c15u)) * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The seed of one pixel's dimension (or pair of dimensions) `dimension` under render seed `seed`.
uint sobol_seed(uint pixel, uint seed, uint dimension) {
    return hash_combine(hash_combine(seed, dimension), pixel);
}

// A 32-bit fraction as a float in [0, 1): its top 24 bits (at most 1 - 2^-24).
float fraction_to_float(uint x) {
    return float(x >> 8u) * (1.0f / 16777216.0f);
}

// Point `sample_index` of the 2D dimension with seed `seed`. owen(reverse(y)) = reverse(LK(y)): each scramble of a
// value costs one reversal.
vec2 sample_sobol_2d(uint sample_index, uint seed) {
    uint i = nested_uniform_scramble(sample_index, seed);
    uint x0 = bitfieldReverse(laine_karras_permutation(i, hash_combine(seed, 1u)));
    uint x1 = bitfieldReverse(laine_karras_permutation(sobol_dimension_1_reversed(i), hash_combine(seed, 2u)));
    return vec2(fraction_to_float(x0), fraction_to_float(x1));
}

// Point `sample_index` of the 1D dimension with seed `seed`.
float sample_sobol_1d(uint sample_index, uint seed) {
    uint i = nested_uniform_scramble(sample_index, seed);
    return fraction_to_float(bitfieldReverse(laine_karras_permutation(i, hash_combine(seed, 1u))));
}

#endif
