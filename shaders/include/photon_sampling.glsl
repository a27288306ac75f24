// Sampling one scattering from uniform random numbers and random words: the polar cosine
// (Henyey-Greenstein or the tabulated phase function), the exponential free path and the azimuth
// without libm calls, and the turn of the direction. Part of photon_step.glsl (included from it
// after PhotonDerived; not used on its own).
#ifndef VPSIM_PHOTON_SAMPLING
#define VPSIM_PHOTON_SAMPLING

// Henyey-Greenstein: cos(theta) from a uniform u in (0,1] (inverse of its CDF).
float photonHgCos(PHOTON_DERIVED_IN k, float u) {
    if (k.hgInvTwoG == float(0)) return float(2) * u - float(1);
    float t = k.hgOneMinusG2 / (k.hgOneMinusG + k.hgTwoG * u);
    return clamp((k.hgOnePlusG2 - t * t) * k.hgInvTwoG, float(-1), float(1));
}

// Tabulated phase function: linear interpolation of the inverse CDF at u.
float photonTableCos(uint n, float u) {
    float x = u * float(n - 1u);
    int i = min(int(x), int(n) - 2);
    float f = x - float(i);
    return mix(photonPhaseTable(i), photonPhaseTable(i + 1), f);
}

// -ln(u) for the uniform u = (m + 1) 2^-24 that rngUniform makes of the same 32 bits (m their top
// 24): an exponential deviate with mean 1, without calling log (a call in the step loop makes the
// CPU path spill its registers). x = m + 1 = 2^e f with f in [sqrt(1/2), sqrt(2)) by integer
// operations on its bits, ln f = 2 atanh(s) with s = (f - 1)/(f + 1), |s| < 0.172, as a series to
// s^9 (truncation below 7e-10), so -ln(u) = (24 - e) ln 2 - ln f: exact at u = 1 and never negative.
float photonExponential(uint bits) {
    uint shifted = floatBitsToUint(float((bits >> 8) + 1u)) - 0x3F3504F3u;
    float f = uintBitsToFloat((shifted & 0x7FFFFFu) + 0x3F3504F3u);
    float s = (f - float(1)) / (f + float(1));
    float s2 = s * s;
    float s4 = s2 * s2;
    float lnF = s * ((float(2) + s2 * float(2.0 / 3.0)) + s4 * ((float(0.4) + s2 * float(2.0 / 7.0)) +
                                                                s4 * float(2.0 / 9.0)));
    return float(24 - int(shifted >> 23)) * float(0.6931471805599453) - lnF;
}

// (cos, sin) of a uniform azimuth drawn from 32 random bits, without sin and cos (on the CPU
// path sincosf, with its argument-range branches, took a fifth of the step's time). The top two bits
// pick a quadrant q, the next 22 an angle a uniform in [-pi/4, pi/4] (centres of 2^22 equal
// steps), and the azimuth is q pi/2 + a. sin a and cos a are Taylor series to a^9 and a^8
// (truncation below 2e-9 and 3e-8, under float's rounding), evaluated by Estrin's scheme (short
// dependency chains); the quadrant turns (cos a, sin a) by arithmetic, not branches.
vec2 photonAzimuth(uint bits) {
    uint quadrant = bits >> 30;
    float a = (float((bits >> 8) & 0x3FFFFFu) - float(2097151.5)) * float(1.5707963267948966 / 4194304.0);
    float a2 = a * a;
    float a4 = a2 * a2;
    float sinPoly = (float(-1.0 / 6.0) + a2 * float(1.0 / 120.0)) +
                    a4 * (float(-1.0 / 5040.0) + a2 * float(1.0 / 362880.0));
    float cosPoly = (float(-0.5) + a2 * float(1.0 / 24.0)) +
                    a4 * (float(-1.0 / 720.0) + a2 * float(1.0 / 40320.0));
    float s = a + (a * a2) * sinPoly;
    float c = float(1) + a2 * cosPoly;
    // q = 0..3: (c, s), (-s, c), (-c, -s), (s, -c): an odd q swaps the two (a bit mask selects),
    // and the sign bits flip for q = 1, 2 (cos) and q = 2, 3 (sin).
    uint swap = 0u - (quadrant & 1u);
    uint cBits = floatBitsToUint(c), sBits = floatBitsToUint(s);
    uint x = (cBits & ~swap) | (sBits & swap);
    uint y = (sBits & ~swap) | (cBits & swap);
    x ^= (((quadrant + 1u) >> 1) & 1u) << 31;
    y ^= (quadrant >> 1) << 31;
    return vec2(uintBitsToFloat(x), uintBitsToFloat(y));
}

// Turns direction d by polar angle theta (cos given) and azimuth phi about itself.
vec3 photonRotate(vec3 d, float cosT, float cosP, float sinP) {
    float sinT2 = max(float(0), float(1) - cosT * cosT);
    vec3 n;
    if (d.z * d.z > float(0.99999)) {
        float sinT = sqrt(sinT2);
        float s = d.z > float(0) ? float(1) : float(-1);
        n = vec3(sinT * cosP, sinT * sinP, s * cosT);
    } else {
        // With t = sqrt(1 - dz^2) only sinT / t and sinT t = (sinT / t) t^2 appear: one square
        // root and one division.
        float t2 = float(1) - d.z * d.z;
        float sinTOverT = sqrt(sinT2 / t2);
        n.x = sinTOverT * (d.x * d.z * cosP - d.y * sinP) + d.x * cosT;
        n.y = sinTOverT * (d.y * d.z * cosP + d.x * sinP) + d.y * cosT;
        n.z = -sinTOverT * cosP * t2 + d.z * cosT;
    }
    // One Newton step towards |n| = 1 (n (3 - |n|^2) / 2): |n|^2 = 1 + e becomes 1 - 3e^2/4, so
    // float round-off cannot drift |d| over hundreds of scatterings, without a sqrt and a divide.
    return n * (float(1.5) - float(0.5) * dot(n, n));
}

#endif
