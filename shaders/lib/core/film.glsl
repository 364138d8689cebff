// The film's fixed-point sums (layout.h FilmPixel): adding a float sample exactly to a 128-bit two's complement
// integer, and reading one back as a float. Integer addition is associative, so any split of the samples over
// waves, runs or machines gives the same bits. GLSL only; engine/render/film.h is the host side.
#ifndef FH_FILM_GLSL
#define FH_FILM_GLSL

// a + b, 128 bits, carries propagated (wraps modulo 2^128).
uvec4 add_fixed(uvec4 a, uvec4 b) {
    uvec4 r;
    uint carry, c;
    r.x = uaddCarry(a.x, b.x, carry);
    r.y = uaddCarry(a.y, b.y, c);
    r.y = uaddCarry(r.y, carry, carry);
    carry += c;
    r.z = uaddCarry(a.z, b.z, c);
    r.z = uaddCarry(r.z, carry, carry);
    carry += c;
    r.w = a.w + b.w + carry;
    return r;
}

const uvec4 FIXED_NAN = uvec4(0u, 0u, 0u, FILM_NAN_TOP_WORD);  // layout.h
bool is_fixed_nan(uvec4 a) { return a == FIXED_NAN; }

uvec4 negate_fixed(uvec4 a) { return add_fixed(~a, uvec4(1u, 0u, 0u, 0u)); }

// v x 2^FILM_FRACTION_BITS rounded to the nearest integer (halves away from zero), as 128-bit two's complement.
// False for NaN, infinity and |v| >= 2^FILM_MAX_LOG2, which the film cannot hold.
bool encode_fixed(float v, out uvec4 fixed_value) {
    fixed_value = uvec4(0u);
    uint bits = floatBitsToUint(v);
    uint biased = (bits >> 23u) & 0xffu;
    if (int(biased) - 126 > FILM_MAX_LOG2) return false;  // |v| >= 2^FILM_MAX_LOG2, infinity, NaN
    uint mantissa = bits & 0x7fffffu;
    if (biased != 0u) mantissa |= 0x800000u;
    else biased = 1u;  // subnormal
    int shift = int(biased) - 150 + FILM_FRACTION_BITS;  // |v| x 2^F = mantissa x 2^shift
    uvec4 magnitude = uvec4(0u);
    if (shift < 0) {
        uint right = uint(-shift);
        if (right <= 24u) magnitude.x = (mantissa + (1u << (right - 1u))) >> right;
    } else {
        uint word = uint(shift) >> 5u, bit = uint(shift) & 31u;
        magnitude[word] = mantissa << bit;
        if (bit != 0u && word < 3u) magnitude[word + 1u] = mantissa >> (32u - bit);
    }
    fixed_value = (bits >> 31u) != 0u ? negate_fixed(magnitude) : magnitude;
    return true;
}

// The value as a float (rounded; exact when it is a float, e.g. a sum kept as plain float sums).
float decode_fixed(uvec4 a) {
    if (is_fixed_nan(a)) return uintBitsToFloat(0x7fc00000u);
    bool negative = (a.w >> 31u) != 0u;
    uvec4 m = negative ? negate_fixed(a) : a;
    // Highest word first: each word's bits are a slice of the value, so for a float-valued sum every step is exact.
    float value = float(m.w) * 79228162514264337593543950336.0f;  // 2^96
    value += float(m.z) * 18446744073709551616.0f;                 // 2^64
    value += float(m.y) * 4294967296.0f;                           // 2^32
    value += float(m.x);
    value *= exp2(-float(FILM_FRACTION_BITS));
    return negative ? -value : value;
}

#endif
