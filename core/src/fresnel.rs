//! Refraction and unpolarised Fresnel reflectance (eqs. 5–7, docs/conventions.md §3).

use crate::lane::Lane;

/// Unpolarised Fresnel reflectance from the cosines of the incident and
/// transmitted angles and the index ratio `r = n_t / n_i` (eq. 6 in the
/// `r_s, r_p` form, exact at normal incidence where the printed sine form is
/// 0/0): `f = (r_s² + r_p²) / 2` with
/// `r_s = (cos_i − r cos_t)/(cos_i + r cos_t)`, `r_p = (r cos_i − cos_t)/(r cos_i + cos_t)`.
/// Exactly 0 for `r = 1` (no interface) and in `[0, 1]` for cosines in `[0, 1]`.
#[inline]
#[must_use]
pub fn fresnel_from_cosines<L: Lane>(cos_i: L, cos_t: L, r: L) -> L {
    let one = L::c(1.0);
    let rc_t = r * cos_t;
    let rc_i = r * cos_i;
    let s_den = cos_i + rc_t;
    let p_den = rc_i + cos_t;
    // Both denominators vanish only when both cosines are 0 (grazing with
    // r = 1), which the r = 1 select below covers; guard the division anyway.
    let degenerate = s_den.eq(L::c(0.0)) | p_den.eq(L::c(0.0));
    let s_den = L::select(degenerate, one, s_den);
    let p_den = L::select(degenerate, one, p_den);
    let rs = (cos_i - rc_t) / s_den;
    let rp = (rc_i - cos_t) / p_den;
    let f = L::c(0.5) * (rs * rs + rp * rp);
    let f = L::select(degenerate, one, f);
    L::select(r.eq(one), L::c(0.0), f)
}

/// Cosine of the transmitted angle by Snell's law (eq. 7) for an index ratio
/// `r = n_t / n_i`, and a mask of the lanes under total internal reflection
/// (`sin θt > 1`), whose cosine is returned as 0.
///
/// Evaluated as `cos θt = sqrt((r − 1)(r + 1) + cos²θi) / r`, which equals
/// `sqrt(1 − sin²θi / r²)` but keeps full relative accuracy near grazing
/// incidence and for `r` close to 1 (the naive form cancels catastrophically
/// there). At `r = 1` it returns `cos θi` exactly.
#[inline]
#[must_use]
pub fn refract_cos<L: Lane>(cos_i: L, r: L) -> (L, L::Mask) {
    let one = L::c(1.0);
    let q = (r - one) * (r + one) + cos_i * cos_i;
    let tir = q.lt(L::c(0.0));
    (L::select(tir, L::c(0.0), q.sqrt() / r), tir)
}

/// Unpolarised Fresnel reflectance `f(α, r)` (eqs. 6–7) for a ray with
/// `cos α = cos_i` meeting an interface of index ratio `r = n_t / n_i > 0`:
/// `((r−1)/(r+1))²` at normal incidence, 1 at grazing incidence and under
/// total internal reflection, 0 for `r = 1`.
#[inline]
#[must_use]
pub fn fresnel<L: Lane>(cos_i: L, r: L) -> L {
    let (cos_t, tir) = refract_cos(cos_i, r);
    L::select(tir, L::c(1.0), fresnel_from_cosines(cos_i, cos_t, r))
}

/// Solid-angle factor `dω′ = cos θi / (n² cos θi′)` (eq. 5, with dω = 1).
/// Where `cos θi′ = 0` (only `n = 1` at grazing) it takes its limit `1/n²`.
#[inline]
#[must_use]
pub fn solid_angle<L: Lane>(cos_i: L, cos_i_refracted: L, n: L) -> L {
    let n2 = n * n;
    let ok = L::c(0.0).lt(cos_i_refracted);
    let den = L::select(ok, n2 * cos_i_refracted, n2);
    let num = L::select(ok, cos_i, L::c(1.0));
    num / den
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_is_exact() {
        for &n in &[1.1f64, 1.3, 1.5, 1.7, 2.4] {
            let want = ((n - 1.0) / (n + 1.0)) * ((n - 1.0) / (n + 1.0));
            assert!((fresnel(1.0f64, n) - want).abs() <= 2.0 * f64::EPSILON * want);
        }
        assert!((fresnel(1.0f64, 1.5) - 0.04).abs() < 1e-16);
        assert!((fresnel(1.0f32, 1.5) - 0.04).abs() <= 2.0 * 0.04 * f32::EPSILON);
    }

    #[test]
    fn grazing_tir_and_matched_index() {
        assert_eq!(fresnel(0.0f64, 1.5), 1.0);
        assert_eq!(fresnel(0.0f32, 1.5), 1.0);
        let c45 = core::f64::consts::FRAC_1_SQRT_2;
        assert_eq!(fresnel(c45, 1.0 / 1.5), 1.0);
        for &c in &[0.0f64, 0.3, 0.7, 1.0] {
            assert_eq!(fresnel(c, 1.0), 0.0);
        }
    }

    #[test]
    fn solid_angle_limits() {
        assert_eq!(solid_angle(0.0f64, 0.0, 1.0), 1.0);
        assert_eq!(solid_angle(1.0f64, 1.0, 1.5), 1.0 / 2.25);
    }
}
