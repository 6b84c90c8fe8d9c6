//! Data no fitted model matches exactly, where the answer is still known
//! (docs/estimation.md, "When the model does not fit"): a reflectance
//! richer than any model laminar fits, on random designs drawn from a
//! CUReT-like distribution of angles. Its **pseudo-true** parameters are
//! those of the fit to the noise-free truth on a dense design from the same
//! distribution: what a fit converges to as measurements accumulate, and
//! what a misfit-robust interval must cover.
//!
//! The truth ([`Truth::radiance`]): the Gaussian model of eq. 8 at
//! `(σ/T, β, n, a)`, plus a Lambertian term `λ cos θi`, plus a second,
//! sharper surface lobe `μ L^sf(σ₂/T)`, each term scaled to peak 1 over the
//! design distribution before its weight is applied, the sum to peak 1.

use crate::coverage::NoiseModel;
use crate::scene::Scene;
use crate::synthetic::Noise;
use laminar_brdf_core::{
    inverse_slope_squared, surface_radiance, total_radiance, Angles, Correlation, Geometry, Params,
};

/// A reflectance richer than the models (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truth {
    /// The main lobe: the Gaussian model at these parameters.
    pub main: Params,
    /// The Lambertian term's weight λ.
    pub lambert: f64,
    /// The second lobe's σ/T.
    pub second_slope: f64,
    /// The second lobe's weight μ.
    pub second: f64,
}

/// Largest zenith angle of the designs (75°): CUReT's measurements reach
/// about 80°, and few lie beyond 75°.
pub const MAX_ZENITH: f64 = 75.0 * core::f64::consts::PI / 180.0;

/// `k` geometries drawn from a CUReT-like distribution: θi and θs with
/// density ∝ sin θ on [0, 75°] (uniform over the hemisphere's solid angle
/// up to 75°), φs uniform on (−π, π].
pub fn design(k: usize, rng: &mut Noise) -> Vec<Angles> {
    let cos_max = libm::cos(MAX_ZENITH);
    let zenith = |u: f64| libm::acos(1.0 - u * (1.0 - cos_max));
    (0..k)
        .map(|_| {
            let ti = zenith(rng.uniform());
            let ts = zenith(rng.uniform());
            let ps = core::f64::consts::PI * (2.0 * rng.uniform() - 1.0);
            Angles::new(ti, ts, ps).expect("inside the domain")
        })
        .collect()
}

impl Truth {
    /// The truth of the misspecified coverage test: the Gaussian model at
    /// σ/T 0.4, β 0.7, n 1.4, a 0.7, with λ = 0.05 and a second lobe at
    /// σ/T 0.2 of weight μ = 0.15 (chosen so that the exp and gauss fits'
    /// pseudo-true parameters lie inside the default box).
    pub fn standard() -> Self {
        Self {
            main: Params::new(0.4, 0.7, 1.4, 0.7).expect("in the domain"),
            lambert: 0.05,
            second_slope: 0.2,
            second: 0.15,
        }
    }

    /// The three terms at `a`, unscaled: main, Lambertian, second lobe.
    fn terms(&self, a: &Angles) -> [f64; 3] {
        let g = Geometry::<f64>::splat(a);
        [
            total_radiance(&g, Correlation::Gaussian, &self.main),
            libm::cos(a.theta_i()),
            surface_radiance(
                &g,
                Correlation::Gaussian,
                inverse_slope_squared(self.second_slope),
            ),
        ]
    }

    /// The noise-free radiance at `angles`, each term scaled by its max
    /// over `reference` (the dense design) and the sum to peak 1 there.
    pub fn radiance(&self, angles: &[Angles], reference: &[Angles]) -> Vec<f64> {
        let peaks = reference.iter().fold([0.0f64; 3], |m, a| {
            let t = self.terms(a);
            [m[0].max(t[0]), m[1].max(t[1]), m[2].max(t[2])]
        });
        let weights = [1.0, self.lambert, self.second];
        let value = |a: &Angles| {
            let t = self.terms(a);
            (0..3).map(|i| weights[i] * t[i] / peaks[i]).sum::<f64>()
        };
        let peak = reference.iter().map(value).fold(0.0, f64::max);
        angles.iter().map(|a| value(a) / peak).collect()
    }

    /// A scene of the truth on `angles` with `noise` on every measurement
    /// (the uncertainties given to the fit when heteroscedastic); the terms
    /// scaled on `reference`.
    pub fn noisy_scene(
        &self,
        angles: Vec<Angles>,
        reference: &[Angles],
        noise: NoiseModel,
        rng: &mut Noise,
    ) -> Scene {
        let clean = self.radiance(&angles, reference);
        let sigma = noise_sigma(&clean, noise);
        let radiance: Vec<f64> = clean
            .iter()
            .zip(&sigma)
            .map(|(&v, &s)| v + s * rng.normal())
            .collect();
        let given = matches!(noise, NoiseModel::Heteroscedastic { .. }).then_some(sigma);
        scene(angles, radiance, given)
    }

    /// The noise-free scene on `angles` (for the pseudo-true fit), with
    /// the uncertainties `noise` would give, so that its weights are those
    /// of the noisy fits.
    pub fn clean_scene(&self, angles: Vec<Angles>, noise: NoiseModel) -> Scene {
        let clean = self.radiance(&angles, &angles);
        let given =
            matches!(noise, NoiseModel::Heteroscedastic { .. }).then(|| noise_sigma(&clean, noise));
        scene(angles, clean, given)
    }
}

/// The standard deviation of `noise` at each clean value.
fn noise_sigma(clean: &[f64], noise: NoiseModel) -> Vec<f64> {
    clean
        .iter()
        .map(|&v| match noise {
            NoiseModel::Every(s) => s,
            NoiseModel::Heteroscedastic { floor, relative } => floor + relative * v,
        })
        .collect()
}

fn scene(angles: Vec<Angles>, radiance: Vec<f64>, sigma: Option<Vec<f64>>) -> Scene {
    let nonpositive = radiance.iter().filter(|&&v| v <= 0.0).count();
    let rows = (1..=angles.len()).collect();
    Scene::from_radiance(angles, radiance, rows, nonpositive, sigma)
}
