// Owen-scrambled Sobol' points, four dimensions at a time (Burley 2020, "Practical Hash-based Owen Scrambling",
// JCGT 9(4)): the stratified, low-discrepancy sampler (`--sampler sobol`). Shared GLSL/C++ subset.
//
// A pixel's sample i draws each block of four dimensions from the first four Sobol' dimensions at a shuffled index:
//   x = owen(sobol_k(owen(i, seed_block)), hash(seed_block, k))       k = 0..3
// Shuffling the index (a nested uniform scramble of its bits, Owen 1995 as hashed by Laine & Karras 2011) gives every
// block its own random order, so blocks are independent of each other (padding, Kollig & Keller 2002) while each
// block's points stay a (0, m, 2)-net in every pair of dimensions for any power-of-two prefix of the samples; the
// scramble of the values makes every point uniform on [0, 1)^4, so estimates are unbiased. Seeds hash the pixel, the
// render seed and the block, so pixels, seeds and blocks decorrelate; the same (pixel, sample, seed) gives the same
// point (deterministic, resumable, independent of the wave size).
#ifndef FREDHOLM_LIB_SOBOL_GLSL
#define FREDHOLM_LIB_SOBOL_GLSL

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

// The first four Sobol' dimensions of point `index`, as 32-bit fractions: dimension 0 is van der Corput's radical
// inverse; dimensions 1 to 3 XOR the direction numbers of Joe & Kuo 2008 (polynomials x + 1, x^2 + x + 1,
// x^3 + x + 1; initial numbers 1 / 1, 3 / 1, 3, 1), generated here by their recurrences instead of read from a table:
// v_i = v_{i-s} ^ (v_{i-s} >> s) ^ (the polynomial's inner terms).
uvec4 sobol_4d(uint index) {
    uvec4 x = uvec4(bitfieldReverse(index), 0u, 0u, 0u);
    uint v1 = 0x80000000u;
    uint v2a = 0x80000000u;  // dimension 2: v_i, v_{i+1}
    uint v2b = 0xc0000000u;
    uint v3a = 0x80000000u;  // dimension 3: v_i, v_{i+1}, v_{i+2}
    uint v3b = 0xc0000000u;
    uint v3c = 0x20000000u;
    for (uint rest = index; rest != 0u; rest >>= 1u) {
        if ((rest & 1u) != 0u) {
            x.y ^= v1;
            x.z ^= v2a;
            x.w ^= v3a;
        }
        v1 ^= v1 >> 1u;
        uint v2 = v2a ^ (v2a >> 2u) ^ v2b;
        v2a = v2b;
        v2b = v2;
        uint v3 = v3a ^ (v3a >> 3u) ^ v3b;
        v3a = v3b;
        v3b = v3c;
        v3c = v3;
    }
    return x;
}

// A hash of two words (the PCG output permutation over a multiply-xorshift mix): seeds per pixel, block and dimension.
uint hash_combine(uint a, uint b) {
    uint state = (a ^ (b * 0x9e3779b9u + 0x7f4a7c15u)) * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// The seed of one pixel's block of four dimensions under render seed `seed`.
uint sobol_block_seed(uint pixel, uint seed, uint block) {
    return hash_combine(hash_combine(seed, block), pixel);
}

// Point `sample_index` of the block with seed `block_seed`: four floats in [0, 1), 24 bits each (at most 1 - 2^-24).
vec4 sample_sobol_block(uint sample_index, uint block_seed) {
    uvec4 x = sobol_4d(nested_uniform_scramble(sample_index, block_seed));
    vec4 u;
    for (int k = 0; k < 4; ++k) {
        u[k] = float(nested_uniform_scramble(x[k], hash_combine(block_seed, uint(k) + 1u)) >> 8u) * (1.0f / 16777216.0f);
    }
    return u;
}

#endif
