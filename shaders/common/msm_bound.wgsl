// The moment bound of moment shadow maps and moment-based OIT (Peters & Klein 2015, Hamburger bound; MBOIT,
// Münstermann et al. 2018, computeTransmittanceAtDepthFrom4/6PowerMoments): normalise and bias the moments,
// factorise the Hankel matrix, find the canonical representation's other support points, integrate the
// interpolating polynomial (1 in front of z, the overestimation weight at z, 0 behind); V = exp(-b_0 clamp(fraction,
// 0, 1)) (visibility::msm, expression for expression: fma exactly where the CPU model uses mul_add). Shared by the
// shadow method's lookup (methods/msm.wgsl) and the eye technique (transparency/mboit.wgsl); x = 2z - 1.
#include "common/visibility.wgsl"

// True for a finite f32 (WGSL has no isfinite; NaN fails every comparison).
fn msm_finite(v: f32) -> bool {
    return abs(v) <= 3.4028235e38;
}

// 1 if support point zi lies in front of x.
fn msm_in_front(zi: f32, x: f32) -> f32 {
    return select(0.0, 1.0, zi < x);
}

fn msm_quadratic_roots(c0: f32, c1: f32, c2: f32) -> vec2<f32> {
    let p = c1 / c2;
    let q = c0 / c2;
    let r = sqrt(max(p * p * 0.25 - q, 0.0));
    return vec2<f32>(-p * 0.5 - r, -p * 0.5 + r);
}

fn msm_cubic_roots(c0: f32, c1: f32, c2: f32, c3: f32) -> vec3<f32> {
    let a = c0 / c3;
    let b = c1 / c3 / 3.0;
    let c = c2 / c3 / 3.0;
    let dx = b - c * c;
    let dy = a - b * c;
    let dz = c * a - b * b;
    let disc = 4.0 * dx * dz - dy * dy;
    let depressed = dy - 2.0 * c * dx;
    let theta = atan2(sqrt(max(disc, 0.0)), -depressed) / 3.0;
    let cr = cos(theta);
    let ci = sin(theta);
    let s = 2.0 * sqrt(max(-dx, 0.0));
    let r = vec3<f32>(
        s * cr - c,
        s * (-0.5 * cr - 0.8660254 * ci) - c,
        s * (-0.5 * cr + 0.8660254 * ci) - c,
    );
    return vec3<f32>(
        msm_polish(c0, c1, c2, c3, msm_polish(c0, c1, c2, c3, r.x)),
        msm_polish(c0, c1, c2, c3, msm_polish(c0, c1, c2, c3, r.y)),
        msm_polish(c0, c1, c2, c3, msm_polish(c0, c1, c2, c3, r.z)),
    );
}

// One Newton step on c0 + c1 t + c2 t^2 + c3 t^3, skipped where not finite: the roots then do not depend on
// the precision of atan2, cos and sin.
fn msm_polish(c0: f32, c1: f32, c2: f32, c3: f32, r: f32) -> f32 {
    let p = ((c3 * r + c2) * r + c1) * r + c0;
    let dp = (3.0 * c3 * r + 2.0 * c2) * r + c1;
    let step = p / dp;
    return select(r, r - step, msm_finite(step));
}

fn msm_fraction_4(m1: f32, m2: f32, m3: f32, m4: f32, x: f32, w: f32) -> f32 {
    let d11 = fma(-m1, m1, m2);
    let l21d11 = fma(-m1, m2, m3);
    let l21 = l21d11 / d11;
    let d22 = fma(-l21d11, l21, fma(-m2, m2, m4));
    var c1 = x - m1;
    var c2 = x * x - (m2 + l21 * c1);
    c1 /= d11;
    c2 /= d22;
    c1 -= l21 * c2;
    let c0 = 1.0 - (m1 * c1 + m2 * c2);
    let z = msm_quadratic_roots(c0, c1, c2);
    let f0 = w;
    let f1 = msm_in_front(z.x, x);
    let f2 = msm_in_front(z.y, x);
    let f01 = (f1 - f0) / (z.x - x);
    let f12 = (f2 - f1) / (z.y - z.x);
    let f012 = (f12 - f01) / (z.y - x);
    let p2 = f012;
    let p1a = f01 - f012 * z.x;
    let p0 = f0 - p1a * x;
    let p1 = p1a - p2 * x;
    return p0 + p1 * m1 + p2 * m2;
}

fn msm_fraction_6(m1: f32, m2: f32, m3: f32, m4: f32, m5: f32, m6: f32, x: f32, w: f32) -> f32 {
    let d11 = fma(-m1, m1, m2);
    let l21d11 = fma(-m1, m2, m3);
    let l21 = l21d11 / d11;
    let d22 = fma(-l21d11, l21, fma(-m2, m2, m4));
    let l31d11 = fma(-m1, m3, m4);
    let l31 = l31d11 / d11;
    let l32d22 = fma(-l21d11, l31, fma(-m2, m3, m5));
    let l32 = l32d22 / d22;
    let d33 = fma(-m3, m3, m6) - (l31d11 * l31 + l32d22 * l32);
    let x2 = x * x;
    var c1 = x - m1;
    var c2 = x2 - (m2 + l21 * c1);
    var c3 = x2 * x - (m3 + (l31 * c1 + l32 * c2));
    c1 /= d11;
    c2 /= d22;
    c3 /= d33;
    c2 -= l32 * c3;
    c1 -= l21 * c2 + l31 * c3;
    let c0 = 1.0 - (m1 * c1 + m2 * c2 + m3 * c3);
    let z = msm_cubic_roots(c0, c1, c2, c3);
    let f0 = w;
    let f1 = msm_in_front(z.x, x);
    let f2 = msm_in_front(z.y, x);
    let f3 = msm_in_front(z.z, x);
    let f01 = (f1 - f0) / (z.x - x);
    let f12 = (f2 - f1) / (z.y - z.x);
    let f23 = (f3 - f2) / (z.z - z.y);
    let f012 = (f12 - f01) / (z.y - x);
    let f123 = (f23 - f12) / (z.z - z.x);
    let f0123 = (f123 - f012) / (z.z - x);
    let a1 = f0123;
    let a0 = f012 - f0123 * z.y;
    let b2 = a1;
    let b1 = a0 - a1 * z.x;
    let b0 = f01 - a0 * z.x;
    let p3 = b2;
    let p2 = b1 - b2 * x;
    let p1 = b0 - b1 * x;
    let p0 = f0 - b0 * x;
    return p0 + p1 * m1 + p2 * m2 + p3 * m3;
}

// The bound's fraction in front of x from the normalised, biased moments m[0..n), n = 4 or 6.
fn msm_fraction(m: array<f32, 6>, x: f32, w: f32, moments: u32) -> f32 {
    if moments == 6u {
        return msm_fraction_6(m[0], m[1], m[2], m[3], m[4], m[5], x, w);
    }
    return msm_fraction_4(m[0], m[1], m[2], m[3], x, w);
}

// V(z) = exp(-b_0 clamp(fraction, 0, 1)) from one texel's sums lo = (b_0, b_1, b_2, b_3), hi = (b_4, b_5, b_6, _):
// visibility::msm::visibility with `moments` (4 or 6), bias beta and overestimation w; 1 where b_0 <= 0.
fn msm_bound_visibility(lo: vec4<f32>, hi: vec4<f32>, z: f32, moments: u32, beta: f32, w: f32) -> f32 {
    let b0 = lo.x;
    if !(b0 > 0.0) {
        return 1.0;
    }
    let keep = 1.0 - beta;
    let six = moments == 6u;
    // MBOIT's f32 bias vectors: (0, 0.375, 0, 0.375) for 4 moments, (0, 0.48, 0, 0.451, 0, 0.45) for 6.
    let v2 = select(0.375, 0.48, six);
    let v4 = select(0.375, 0.451, six);
    let m = array<f32, 6>(
        (lo.y / b0) * keep + 0.0 * beta,
        (lo.z / b0) * keep + v2 * beta,
        (lo.w / b0) * keep + 0.0 * beta,
        (hi.x / b0) * keep + v4 * beta,
        (hi.y / b0) * keep + 0.0 * beta,
        (hi.z / b0) * keep + 0.45 * beta,
    );
    let x = z * 2.0 - 1.0;
    var f = msm_fraction(m, x, w, moments);
    if !msm_finite(f) {
        // A support point rounded onto x: once more a nudge (2^-20) behind.
        f = msm_fraction(m, x + 9.536743e-7, w, moments);
    }
    var fraction = clamp(f, 0.0, 1.0);
    if !msm_finite(f) {
        // Singular in f32: all absorbance at the mean, weighted w within one standard deviation of it.
        let d = x - m[0];
        let step = select(0.0, 1.0, x > m[0]);
        fraction = select(step, w, d * d <= m[1] - m[0] * m[0]);
    }
    return transmittance(b0 * fraction);
}
