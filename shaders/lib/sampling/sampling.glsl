// Warps of uniform random numbers onto the domains a path tracer samples (directions, triangles, pixel
// filters), an orthonormal shading frame and the MIS weight. Shared GLSL/C++ subset (see cpp_compat.h).
//
// Every function is NaN-free for u in [0,1)^n, including u = 0 and u = 1 - 2^-24.
#ifndef FH_SAMPLING_GLSL
#define FH_SAMPLING_GLSL

const float PI = 3.14159265358979f;
const float TWO_PI = 6.28318530717959f;
const float INV_PI = 0.318309886183791f;
const float FLOAT_MAX = 3.402823466e38f;
const float ONE_BELOW_ONE = 0.99999994f;  // the largest float below 1

// An orthonormal basis around `n`; to_local maps world vectors to (t, b, n) coordinates (z = n).
struct Frame {
    vec3 t;
    vec3 b;
    vec3 n;
};

// Branchless ONB of Duff et al. 2017, "Building an orthonormal basis, revisited" (JCGT 6(1)), listing 3:
// continuous except across n.z = 0 and free of the n.z = -1 singularity of Frisvad 2012.
Frame make_frame(vec3 n) {
    float s = n.z >= 0.0f ? 1.0f : -1.0f;  // copysign(1, n.z); GLSL sign() would give 0 at n.z = 0
    float a = -1.0f / (s + n.z);
    float b = n.x * n.y * a;
    Frame f;
    f.t = vec3(1.0f + s * n.x * n.x * a, s * b, -s * n.x);
    f.b = vec3(b, s + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

vec3 to_local(Frame f, vec3 v) {
    return vec3(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

vec3 to_world(Frame f, vec3 v) {
    return f.t * v.x + f.b * v.y + f.n * v.z;
}

// Concentric map of the square onto the unit disk (Shirley & Chiu 1997): area preserving, low distortion.
vec2 sample_concentric_disk(vec2 u) {
    vec2 o = 2.0f * u - vec2(1.0f);
    if (o.x == 0.0f && o.y == 0.0f) {
        return vec2(0.0f);
    }
    float r;
    float theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = 0.25f * PI * (o.y / o.x);
    } else {
        r = o.y;
        theta = 0.5f * PI - 0.25f * PI * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// Cosine-weighted hemisphere around +z by Malley's method (lift the disk sample): pdf = cos(theta) / pi.
// The returned z can round to 0 for u on the square's border; callers treat z <= 0 as a failed sample.
vec3 sample_cosine_hemisphere(vec2 u) {
    vec2 d = sample_concentric_disk(u);
    float z = sqrt(max(0.0f, 1.0f - dot(d, d)));
    return vec3(d.x, d.y, z);
}

float pdf_cosine_hemisphere(float cos_theta) {
    return max(cos_theta, 0.0f) * INV_PI;
}

const float INV_TWO_PI = 0.159154943091895f;

// Uniform direction over the hemisphere around +z: pdf = 1 / (2 pi). z = 1 - u.x lies in (0, 1] for u.x in [0, 1).
vec3 sample_uniform_hemisphere(vec2 u) {
    float z = 1.0f - u.x;
    float r = sqrt(max(0.0f, 1.0f - z * z));
    float phi = TWO_PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Uniform point on a triangle as barycentrics (b1, b2) of its second and third vertex (b0 = 1 - b1 - b2),
// with the low-distortion square-to-triangle map of Heitz 2019 ("A Low-Distortion Map Between Triangle
// and Square", as written in pbrt-v4 SampleUniformTriangle). b1 + b2 = max(u.x, u.y) < 1.
vec2 sample_uniform_triangle(vec2 u) {
    float b0;
    float b1;
    if (u.x < u.y) {
        b0 = 0.5f * u.x;
        b1 = u.y - b0;
    } else {
        b1 = 0.5f * u.y;
        b0 = u.x - b1;
    }
    return vec2(b0, b1);
}

// Uniform point on a camera aperture of circumradius 1, by area: the unit disk (blades < 3, concentric map) or the
// regular polygon with `blades` corners, the first at angle `rotation` (radians) from +x. The polygon is split into
// one triangle per blade, u.x picks the blade and, rescaled, places the point in it with u.y (Heitz 2019).
vec2 sample_aperture(vec2 u, uint blades, float rotation) {
    if (blades < 3u) {
        return sample_concentric_disk(u);
    }
    float n = float(blades);
    float scaled = u.x * n;
    float k = min(floor(scaled), n - 1.0f);
    vec2 b = sample_uniform_triangle(vec2(min(scaled - k, ONE_BELOW_ONE), u.y));
    float a0 = rotation + TWO_PI * k / n;
    float a1 = rotation + TWO_PI * (k + 1.0f) / n;
    return b.x * vec2(cos(a0), sin(a0)) + b.y * vec2(cos(a1), sin(a1));
}

// Inverse error function for |x| < 1 in single precision (Giles 2010, "Approximating the erfinv function",
// GPU Computing Gems Jade, ch. 10): relative error below 4e-7 on the range the filter uses.
float erfinv_approx(float x) {
    float w = -log((1.0f - x) * (1.0f + x));
    float p;
    if (w < 5.0f) {
        w = w - 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

// Pixel-filter offset in [-radius, radius]^2 distributed exactly as the separable Gaussian of standard
// deviation sigma = radius / 3 truncated to that square (pbrt-v4's GaussianFilter without the constant
// offset), so the filter weight of every sample is 1. Each axis inverts the truncated normal CDF:
// x = sigma sqrt(2) erfinv(erf(3 / sqrt(2)) (2u - 1)); the argument stays below erf(3/sqrt(2)) < 1, so
// erfinv's logarithm never sees 0. Exact up to erfinv_approx's error.
vec2 sample_gaussian_filter(vec2 u, float radius) {
    const float ERF_TRUNCATION = 0.997300203936740f;  // erf(3 / sqrt(2)): mass of N(0,1) on [-3, 3]
    vec2 x = ERF_TRUNCATION * (2.0f * u - vec2(1.0f));
    float scale = radius * (1.41421356237310f / 3.0f);  // sigma * sqrt(2)
    vec2 offset = scale * vec2(erfinv_approx(x.x), erfinv_approx(x.y));
    return clamp(offset, vec2(-radius), vec2(radius));
}

// The density sample_gaussian_filter draws offsets from, per unit of area in pixels: the separable Gaussian of
// sigma = radius / 3 normalised over [-radius, radius]^2, 0 outside. Light tracing weights a splat at offset d from a
// pixel's centre by it, as the camera's samples of that pixel are drawn from it (each with the weight 1).
float gaussian_filter_density(vec2 d, float radius) {
    if (abs(d.x) > radius || abs(d.y) > radius) return 0.0f;
    const float ERF_TRUNCATION = 0.997300203936740f;  // erf(3 / sqrt(2)), as sample_gaussian_filter
    float sigma = radius / 3.0f;
    float norm = 1.0f / (sigma * 2.50662827463100f * ERF_TRUNCATION);  // sqrt(2 pi)
    vec2 g = norm * exp(d * d * (-0.5f / (sigma * sigma)));
    return g.x * g.y;
}

// Power heuristic with beta = 2 (Veach 1997, eq. 9.13) for a sample drawn from f, also drawn by g.
// Written as 1 / (1 + (g/f)^2) with the larger pdf as divisor so that huge pdfs neither overflow nor
// give inf/inf; infinite pdfs are clamped to FLOAT_MAX, NaN and negative pdfs count as 0, and (0, 0)
// gives 0. Always finite, in [0, 1].
float power_heuristic(float f_pdf, float g_pdf) {
    float f = f_pdf > 0.0f ? min(f_pdf, FLOAT_MAX) : 0.0f;
    float g = g_pdf > 0.0f ? min(g_pdf, FLOAT_MAX) : 0.0f;
    if (f >= g) {
        if (f == 0.0f) {
            return 0.0f;
        }
        float r = g / f;
        return 1.0f / (1.0f + r * r);
    }
    float r = f / g;
    return r * r / (1.0f + r * r);
}

// Largest channel.
float max_value(vec3 c) {
    return max(c.x, max(c.y, c.z));
}

// Relative luminance of linear Rec. 709 RGB (ITU-R BT.709 primaries, D65).
float luminance(vec3 c) {
    return dot(c, vec3(0.2126f, 0.7152f, 0.0722f));
}

#endif
