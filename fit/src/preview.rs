//! A preview of fitted models: a sphere under a directional light and a
//! constant environment, seen by an orthographic camera along its axis
//! (docs/conventions.md §12).
//!
//! At a pixel of the sphere with normal `n`, the viewer along `v = (0, 0,
//! 1)` and the light along `l`, the radiance is
//! `E · P(θi, θv, φs) · data_scale + L_env · ρ(θv)`: the fitted prediction
//! (`f · cos θi`, in the fitted data's units) lit by a light of irradiance
//! `E`, plus a constant environment of radiance `L_env` reflected with the
//! model's directional albedo ([`crate::albedo`], tabulated over θv and
//! interpolated). θi and θv are the angles of `l` and `v` from `n`, and
//! the azimuth between their projections on the tangent plane gives φs
//! (docs/conventions.md §1). One fitted model per channel: three make an
//! RGB image.

use crate::albedo::albedo_table;
use crate::error::ModelError;
use crate::fitted::FittedModel;
use crate::measurements::MeasurementAngles;

/// The stage of a preview: the image size, the light and the environment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stage {
    /// Image width and height in pixels.
    pub size: usize,
    /// The light's direction from the camera axis (radians).
    pub light_polar: f64,
    /// The light's direction in the image plane, counter-clockwise from
    /// the right (radians).
    pub light_azimuth: f64,
    /// The light's irradiance `E`.
    pub light: f64,
    /// The environment's radiance `L_env`.
    pub environment: f64,
}

impl Default for Stage {
    /// 256 pixels, the light 60° off the axis from the upper left (so the
    /// terminator shows), `E = 1`, `L_env = 0.05`.
    fn default() -> Self {
        Self {
            size: 256,
            light_polar: 60f64.to_radians(),
            light_azimuth: 135f64.to_radians(),
            light: 1.0,
            environment: 0.05,
        }
    }
}

/// A scene option outside what a preview takes.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum StageError {
    /// The image size in pixels.
    #[error("size {0}: must lie in [16, 4096]")]
    Size(usize),
    /// The light's angle from the view axis, degrees.
    #[error("light polar angle {0}: must lie in [0, 89] degrees")]
    LightPolar(f64),
    /// The light's azimuth, degrees.
    #[error("light azimuth {0}: must be a finite number of degrees")]
    LightAzimuth(f64),
    /// The environment's radiance.
    #[error("environment {0}: must be a finite number ≥ 0")]
    Environment(f64),
}

impl Stage {
    /// A scene of `size` pixels with the light's angles in degrees and the
    /// environment's radiance, each [`Stage::default`]'s when `None`.
    ///
    /// # Errors
    /// [`StageError`] naming the first option outside its range.
    pub fn new(
        size: usize,
        light_polar_degrees: Option<f64>,
        light_azimuth_degrees: Option<f64>,
        environment: Option<f64>,
    ) -> Result<Self, StageError> {
        if !(16..=4096).contains(&size) {
            return Err(StageError::Size(size));
        }
        if let Some(p) = light_polar_degrees.filter(|p| !(0.0..=89.0).contains(p)) {
            return Err(StageError::LightPolar(p));
        }
        if let Some(a) = light_azimuth_degrees.filter(|a| !a.is_finite()) {
            return Err(StageError::LightAzimuth(a));
        }
        if let Some(e) = environment.filter(|e| !(*e >= 0.0 && e.is_finite())) {
            return Err(StageError::Environment(e));
        }
        let default = Self::default();
        Ok(Self {
            size,
            light_polar: light_polar_degrees.map_or(default.light_polar, f64::to_radians),
            light_azimuth: light_azimuth_degrees.map_or(default.light_azimuth, f64::to_radians),
            environment: environment.unwrap_or(default.environment),
            ..default
        })
    }
}

/// A rendered preview: linear radiance per pixel and channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    /// Width and height.
    pub size: usize,
    /// Channels (one per fitted model).
    pub channels: usize,
    /// Row-major from the top, channels interleaved; 0 off the sphere.
    pub radiance: Vec<f64>,
    /// Per pixel: whether it shows the sphere.
    pub on_sphere: Vec<bool>,
}

/// View angles at which the albedo is tabulated for the environment term,
/// evenly over `[0, ALBEDO_LAST]`.
const ALBEDO_ANGLES: usize = 90;

/// The last view angle tabulated: 89°. At grazing view (θv = 90°) the
/// quadrature converges slowly (a thousand nodes per dimension); the
/// silhouette's last degree takes the value at 89°.
const ALBEDO_LAST: f64 = 89.0 * core::f64::consts::PI / 180.0;

/// Renders `models` (one per channel) into a preview of `scene`.
///
/// # Errors
/// [`ModelError`] when a model cannot predict (its parameters or
/// constants; a prediction that is not finite).
pub fn render(models: &[FittedModel], scene: &Stage) -> Result<Image, ModelError> {
    let size = scene.size;
    let (sp, cp) = (scene.light_polar.sin(), scene.light_polar.cos());
    let light = [
        sp * scene.light_azimuth.cos(),
        sp * scene.light_azimuth.sin(),
        cp,
    ];
    // Every pixel on the sphere: its index, θv and, when lit, its angles.
    let mut on_sphere = vec![false; size * size];
    let mut pixels = Vec::new();
    let mut lit = Vec::new();
    for row in 0..size {
        for col in 0..size {
            let x = (2.0 * (col as f64 + 0.5) / size as f64) - 1.0;
            let y = 1.0 - (2.0 * (row as f64 + 0.5) / size as f64);
            let r2 = x * x + y * y;
            if r2 >= 1.0 {
                continue;
            }
            let normal = [x, y, (1.0 - r2).sqrt()];
            let index = row * size + col;
            on_sphere[index] = true;
            let cos_v = normal[2];
            pixels.push((index, cos_v.clamp(0.0, 1.0).acos()));
            let cos_i: f64 = (0..3).map(|k| normal[k] * light[k]).sum();
            if cos_i > 0.0 {
                lit.push((index, angles(normal, light, cos_i)?));
            }
        }
    }
    let thetas: Vec<f64> = (0..ALBEDO_ANGLES)
        .map(|i| ALBEDO_LAST * i as f64 / (ALBEDO_ANGLES - 1) as f64)
        .collect();
    let channels = models.len();
    let mut radiance = vec![0.0; size * size * channels];
    let lit_angles: Vec<_> = lit.iter().map(|(_, a)| *a).collect();
    for (c, model) in models.iter().enumerate() {
        let albedo: Vec<f64> = albedo_table(model, &thetas, crate::albedo::Tolerance::DEFAULT)?
            .iter()
            .map(|a| a.albedo)
            .collect();
        for &(index, theta_v) in &pixels {
            radiance[index * channels + c] = scene.environment * interpolate(&albedo, theta_v);
        }
        let direct = model.predict_radiance(&lit_angles)?;
        for (&(index, _), d) in lit.iter().zip(direct) {
            radiance[index * channels + c] += scene.light * d;
        }
    }
    Ok(Image {
        size,
        channels,
        radiance,
        on_sphere,
    })
}

/// The paper-frame angles of light `l` at a point of normal `n` seen along
/// `v = (0, 0, 1)`, `cos θi = n · l > 0`.
fn angles(n: [f64; 3], l: [f64; 3], cos_i: f64) -> Result<laminar_brdf_core::Angles, ModelError> {
    let cos_v = n[2];
    // Projections on the tangent plane, and the azimuth between them.
    let lt: Vec<f64> = (0..3).map(|k| l[k] - cos_i * n[k]).collect();
    let vt: Vec<f64> = (0..3)
        .map(|k| if k == 2 { 1.0 } else { 0.0 } - cos_v * n[k])
        .collect();
    let dot: f64 = (0..3).map(|k| lt[k] * vt[k]).sum();
    let norms =
        (lt.iter().map(|x| x * x).sum::<f64>() * vt.iter().map(|x| x * x).sum::<f64>()).sqrt();
    // Either projection may vanish (light or viewer along n): any azimuth.
    let delta = if norms > 1e-300 {
        (dot / norms).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    };
    MeasurementAngles::Lab {
        theta_i: cos_i.clamp(0.0, 1.0).acos(),
        phi_i: 0.0,
        theta_v: cos_v.clamp(0.0, 1.0).acos(),
        phi_v: delta,
    }
    .paper()
    .map_err(ModelError::OutOfDomain)
}

/// `table` (at equal steps over `[0, ALBEDO_LAST]`) linearly interpolated
/// at `theta` (clamped to that range).
fn interpolate(table: &[f64], theta: f64) -> f64 {
    let last = table.len() - 1;
    let at = (theta / ALBEDO_LAST * last as f64).clamp(0.0, last as f64);
    let i = (at.floor() as usize).min(last.saturating_sub(1));
    let t = at - i as f64;
    table[i] * (1.0 - t) + table[(i + 1).min(last)] * t
}

impl Image {
    /// 8-bit sRGB pixels (RGB; one channel is repeated as grey), exposed so
    /// that the 99.5th percentile of the sphere's radiance over all
    /// channels maps to 0.95 (one exposure for all channels, so colour is
    /// kept), then encoded with the sRGB transfer function. Off the sphere:
    /// a dark grey.
    pub fn to_srgb8(&self) -> Vec<u8> {
        let mut values: Vec<f64> = self
            .on_sphere
            .iter()
            .enumerate()
            .filter(|(_, &on)| on)
            .flat_map(|(i, _)| {
                self.radiance[i * self.channels..(i + 1) * self.channels]
                    .iter()
                    .copied()
            })
            .collect();
        values.sort_by(f64::total_cmp);
        let top = values
            .get((values.len() as f64 * 0.995) as usize)
            .or(values.last())
            .copied()
            .unwrap_or(1.0);
        let exposure = if top > 0.0 { 0.95 / top } else { 1.0 };
        let encode = |v: f64| {
            let v = (v * exposure).clamp(0.0, 1.0);
            let s = if v <= 0.003_130_8 {
                12.92 * v
            } else {
                1.055 * v.powf(1.0 / 2.4) - 0.055
            };
            (s * 255.0).round() as u8
        };
        let mut out = Vec::with_capacity(self.size * self.size * 3);
        for (i, &on) in self.on_sphere.iter().enumerate() {
            for k in 0..3 {
                out.push(if on {
                    encode(self.radiance[i * self.channels + k.min(self.channels - 1)])
                } else {
                    24
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Model, ModelParams};

    fn model(beta: f64) -> FittedModel {
        let params = ModelParams::Layered {
            slope: 0.5,
            beta,
            n: 1.45,
            a: 0.2,
            sub_slope: None,
        };
        FittedModel::with_amplitude(Model::Exp, params, 1.0, 1.0)
    }

    /// Finite, non-negative, lit where the light is: the sphere's point
    /// facing the light is brighter than the point facing away, which has
    /// the environment alone.
    #[test]
    fn a_sphere_is_finite_non_negative_and_lit_where_the_light_is() {
        let scene = Stage {
            size: 64,
            ..Stage::default()
        };
        let image = render(&[model(0.3), model(0.6), model(0.9)], &scene).unwrap();
        assert_eq!(image.radiance.len(), 64 * 64 * 3);
        assert!(image.radiance.iter().all(|v| v.is_finite() && *v >= 0.0));
        // Upper left (towards the light) against lower right.
        let at = |row: usize, col: usize| image.radiance[(row * 64 + col) * 3];
        assert!(
            at(20, 20) > 5.0 * at(44, 44),
            "{} {}",
            at(20, 20),
            at(44, 44)
        );
        assert!(at(44, 44) > 0.0, "the environment lights the shadow side");
        assert!(!image.on_sphere[0] && image.on_sphere[32 * 64 + 32]);
        let srgb = image.to_srgb8();
        assert_eq!(srgb.len(), 64 * 64 * 3);
        assert!(srgb[(20 * 64 + 20) * 3] > srgb[(44 * 64 + 44) * 3]);
    }

    /// With the light off, a pixel's radiance is the environment times the
    /// albedo at its θv, at the centre θv = 0.
    #[test]
    fn the_environment_term_is_the_albedo() {
        let scene = Stage {
            size: 33,
            light: 0.0,
            environment: 2.0,
            ..Stage::default()
        };
        let m = model(0.4);
        let image = render(&[m], &scene).unwrap();
        let centre = image.radiance[16 * 33 + 16];
        let rho = crate::albedo::directional_albedo(
            &m,
            0.0,
            crate::albedo::Tolerance::new(1e-9).unwrap(),
        )
        .unwrap()
        .albedo;
        assert!(
            (centre - 2.0 * rho).abs() < 1e-3 * rho,
            "{centre} against {}",
            2.0 * rho
        );
    }
}
