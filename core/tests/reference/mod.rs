//! A 256-bit reference of every component of the model (docs/conventions.md §2–§3),
//! in `astro-float` (pure-Rust arbitrary precision, correctly rounded
//! elementary functions), written straight from the formulas, without the
//! core's rearrangements. Inputs are the `f64` values the core receives.
#![allow(dead_code)]

use astro_float::{BigFloat, Consts, Radix, RoundingMode};

const P: usize = 256;
const RM: RoundingMode = RoundingMode::ToEven;

/// The reference components, rounded to `f64`, in `Components::NAMES` order.
pub struct Reference {
    cc: Consts,
}

/// Which correlation function.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Corr {
    Gaussian,
    Exponential,
}

impl Reference {
    pub fn new() -> Self {
        Self {
            cc: Consts::new().expect("constants cache"),
        }
    }

    fn f(x: f64) -> BigFloat {
        BigFloat::from_f64(x, P)
    }

    fn sin(&mut self, x: &BigFloat) -> BigFloat {
        x.sin(P, RM, &mut self.cc)
    }
    fn cos(&mut self, x: &BigFloat) -> BigFloat {
        x.cos(P, RM, &mut self.cc)
    }
    fn exp(&mut self, x: &BigFloat) -> BigFloat {
        x.exp(P, RM, &mut self.cc)
    }

    fn rounded(&mut self, x: &BigFloat) -> f64 {
        if x.is_zero() {
            return 0.0;
        }
        let s = x.format(Radix::Dec, RM, &mut self.cc).expect("formats");
        s.parse::<f64>()
            .unwrap_or_else(|_| panic!("cannot parse reference value {s}"))
    }

    /// `L^sf` (eqs. 1–2) from sines and cosines.
    fn surface(
        &mut self,
        corr: Corr,
        (si, ci): (&BigFloat, &BigFloat),
        (ss, cs): (&BigFloat, &BigFloat),
        phi: f64,
        slope: &BigFloat,
    ) -> BigFloat {
        let ph = Self::f(phi);
        let (sp, cp) = (self.sin(&ph), self.cos(&ph));
        let vx = si.sub(&ss.mul(&cp, P, RM), P, RM);
        let vy = ss.mul(&sp, P, RM);
        let vxy2 = vx.mul(&vx, P, RM).add(&vy.mul(&vy, P, RM), P, RM);
        let vz = ci.add(cs, P, RM);
        let vz2 = vz.mul(&vz, P, RM);
        if vz2.is_zero() {
            return Self::f(0.0);
        }
        let lead = ci.div(&vz2, P, RM);
        let x = vxy2.div(&vz2, P, RM).div(&slope.mul(slope, P, RM), P, RM);
        let shape = match corr {
            Corr::Gaussian => {
                let e = x.div(&Self::f(-4.0), P, RM);
                self.exp(&e)
            }
            Corr::Exponential => {
                let one_x = Self::f(1.0).add(&x, P, RM);
                let root = one_x.sqrt(P, RM);
                Self::f(1.0).div(&one_x.mul(&root, P, RM), P, RM)
            }
        };
        lead.mul(&shape, P, RM)
    }

    /// Unpolarised Fresnel reflectance from the two cosines and the ratio `r`.
    fn fresnel(ci: &BigFloat, ct: &BigFloat, r: &BigFloat) -> BigFloat {
        let rct = r.mul(ct, P, RM);
        let rci = r.mul(ci, P, RM);
        let rs = ci.sub(&rct, P, RM).div(&ci.add(&rct, P, RM), P, RM);
        let rp = rci.sub(ct, P, RM).div(&rci.add(ct, P, RM), P, RM);
        rs.mul(&rs, P, RM)
            .add(&rp.mul(&rp, P, RM), P, RM)
            .div(&Self::f(2.0), P, RM)
    }

    /// Every component at `(θi, θs, φs)` for `(σ/T, β, n, a)`, in
    /// `Components::NAMES` order: fresnel_in, fresnel_out, absorb_in,
    /// absorb_out, surface, subsurface, total.
    #[allow(clippy::too_many_arguments)]
    pub fn components(
        &mut self,
        corr: Corr,
        theta_i: f64,
        theta_s: f64,
        phi_s: f64,
        slope: f64,
        beta: f64,
        n: f64,
        a: f64,
    ) -> [f64; 7] {
        let one = Self::f(1.0);
        let (ti, ts) = (Self::f(theta_i), Self::f(theta_s));
        let (si, ci) = (self.sin(&ti), self.cos(&ti));
        let (ss, cs) = (self.sin(&ts), self.cos(&ts));
        let sl = Self::f(slope);
        let nn = Self::f(n);
        let av = Self::f(a);
        let surface = self.surface(corr, (&si, &ci), (&ss, &cs), phi_s, &sl);
        // Snell: sin θ′ = sin θ / n; cos θ′ = sqrt(1 − sin²θ′).
        let refr = |s: &BigFloat| {
            let sp = s.div(&nn, P, RM);
            let cp = one.sub(&sp.mul(&sp, P, RM), P, RM).sqrt(P, RM);
            (sp, cp)
        };
        let (sip, cip) = refr(&si);
        let (ssp, csp) = refr(&ss);
        let f_in = if n == 1.0 {
            Self::f(0.0)
        } else {
            Self::fresnel(&ci, &cip, &nn)
        };
        let f_out = if n == 1.0 {
            Self::f(0.0)
        } else {
            Self::fresnel(&cs, &csp, &nn)
        };
        let t_in = one.sub(&f_in, P, RM);
        let t_out = one.sub(&f_out, P, RM);
        let a_in = av.mul(&ci, P, RM).mul(&ci, P, RM).mul(&t_in, P, RM);
        let a_out = av.mul(&cs, P, RM).mul(&cs, P, RM).mul(&t_out, P, RM);
        let lower = self.surface(corr, (&sip, &cip), (&ssp, &csp), phi_s, &sl);
        let domega = if cip.is_zero() {
            one.div(&nn.mul(&nn, P, RM), P, RM)
        } else {
            ci.div(&nn.mul(&nn, P, RM).mul(&cip, P, RM), P, RM)
        };
        let sub = lower
            .mul(&t_in.sub(&a_in, P, RM), P, RM)
            .mul(&t_out.sub(&a_out, P, RM), P, RM)
            .mul(&domega, P, RM);
        let b = Self::f(beta);
        let total = b
            .mul(&sub, P, RM)
            .add(&one.sub(&b, P, RM).mul(&surface, P, RM), P, RM);
        [f_in, f_out, a_in, a_out, surface, sub, total].map(|v| self.rounded(&v))
    }
}
