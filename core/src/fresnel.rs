//! Refraction and unpolarised Fresnel reflectance (eqs. 5–7, docs/conventions.md §3).

use crate::lane::Lane;

/// Unpolarised Fresnel reflectance `f` and transmittance `t = 1 − f` from
/// the cosines of the incident and transmitted angles and the index ratio
/// `r = n_t / n_i` (eq. 6 in the `r_s, r_p` form, exact at normal incidence
/// where the printed sine form is 0/0), each to a few ulps relative.
///
/// With `S = cos_i + r cos_t`, `P = r cos_i + cos_t` and Snell's law
/// (`r² cos²_t = r² − 1 + cos²_i`), the amplitudes are
/// `r_s = −(r² − 1)/S²` and `r_p = (r² − 1)((r² + 1) cos²_i − 1)/(r² P²)`:
/// the factor `r² − 1 = (r − 1)(r + 1)` is explicit, so `f` keeps its
/// relative accuracy as `r → 1` (the textbook numerators `cos_i − r cos_t`
/// cancel there). `t = 2 r cos_i cos_t (1/S² + 1/P²)` has no cancellation,
/// so it stays accurate near grazing incidence, where `f → 1`. The smaller
/// of the two is kept and the larger is 1 minus it, so `f + t = 1` up to
/// one rounding.
/// `f = 0, t = 1` for `r = 1` (no interface); `f = 1, t = 0` at grazing
/// incidence (`cos_i = 0`). Both lie in `[0, 1]` for cosines in `[0, 1]`.
/// Accuracy (crate docs, Accuracy): `f` within 7.1 ulps (f64) and 7.0 (f32).
#[inline]
#[must_use]
pub fn fresnel_pair<L: Lane>(cos_i: L, cos_t: L, r: L) -> (L, L) {
    let one = L::c(1.0);
    let zero = L::c(0.0);
    let s_den = cos_i + r * cos_t;
    let p_den = r * cos_i + cos_t;
    // Both sums vanish only when both cosines are 0 (grazing with r = 1).
    let degenerate = s_den.eq(zero) | p_den.eq(zero);
    let s_den = L::select(degenerate, one, s_den);
    let p_den = L::select(degenerate, one, p_den);
    let (s2, p2) = (s_den * s_den, p_den * p_den);
    let r2m1 = (r - one) * (r + one);
    let r2 = r * r;
    let rs = r2m1 / s2;
    let rp = r2m1 * ((r2 + one) * (cos_i * cos_i) - one) / (r2 * p2);
    // At normal incidence eq. 6 is ((r − 1)/(r + 1))², with two roundings.
    let normal = (r - one) / (r + one);
    let f = L::select(
        cos_i.eq(one),
        normal * normal,
        L::c(0.5) * (rs * rs + rp * rp),
    );
    let t = L::c(2.0) * r * cos_i * cos_t * (one / s2 + one / p2);
    // Each is accurate on its own; the smaller one is then taken as computed
    // and the larger as 1 minus it (no cancellation: it is at least 1/2), so
    // that f + t = 1 up to one rounding, as energy conservation asks.
    let f_small = f.le(t);
    let f = L::select(f_small, f, one - t).min(one);
    let t = L::select(f_small, one - f, t).min(one);
    // Grazing incidence reflects everything (t has the factor cos_i, so it
    // is already 0 there; f would be 1 only up to rounding).
    let reflects_all = degenerate | cos_i.eq(zero);
    let no_interface = r.eq(one);
    (
        L::select(no_interface, zero, L::select(reflects_all, one, f)),
        L::select(no_interface, one, L::select(degenerate, zero, t)),
    )
}

/// Unpolarised Fresnel reflectance from the cosines of the incident and
/// transmitted angles and the index ratio `r = n_t / n_i`: the `f` of
/// [`fresnel_pair`].
#[inline]
#[must_use]
pub fn fresnel_from_cosines<L: Lane>(cos_i: L, cos_t: L, r: L) -> L {
    fresnel_pair(cos_i, cos_t, r).0
}

/// Fresnel transmittance `1 − f` from the cosines: the `t` of
/// [`fresnel_pair`], accurate where `f → 1`.
#[inline]
#[must_use]
pub fn transmittance_from_cosines<L: Lane>(cos_i: L, cos_t: L, r: L) -> L {
    fresnel_pair(cos_i, cos_t, r).1
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

/// Fresnel transmittance `1 − f(α, r)` (eqs. 6–7), computed without the
/// subtraction (see [`fresnel_pair`]); 0 under total internal reflection.
#[inline]
#[must_use]
pub fn transmittance<L: Lane>(cos_i: L, r: L) -> L {
    let (cos_t, tir) = refract_cos(cos_i, r);
    L::select(tir, L::c(0.0), transmittance_from_cosines(cos_i, cos_t, r))
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
