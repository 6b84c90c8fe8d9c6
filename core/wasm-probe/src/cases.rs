//! The cases of the wasm parity probe, shared by the wasm module
//! (`main.rs`) and the native test (`tests/wasm_parity.rs`).
//!
//! Value `i` is decoded as (geometry, parameter set, correlation, output),
//! outputs being the seven model components plus Jensen and Oren–Nayar.

use core::f64::consts::{FRAC_PI_2, PI};
use laminar_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_core::{components, f32x8, Angles, Correlation, Geometry, Lane, Params};

/// Geometries probed (a multiple of 8).
pub const GEOMETRIES: u32 = 64;
const PARAMS: u32 = 6;
const OUTPUTS: u32 = 9;
const PER_GEOMETRY: u32 = PARAMS * 2 * OUTPUTS;

/// Number of probed values.
pub fn count() -> u32 {
    GEOMETRIES * PER_GEOMETRY
}

/// Geometry `g`: hard cases first (normal, grazing, φs wrap), then a
/// deterministic spread over the hemisphere.
pub fn angles(g: u32) -> Angles {
    let hard = [
        (0.0, 0.0, 0.0),
        (0.0, 1e-6, 0.0),
        (FRAC_PI_2, FRAC_PI_2, 0.0),
        (FRAC_PI_2, 0.3, PI),
        (0.7, 0.7, 0.0),
        (0.7, 0.7, -PI),
        (1.2, FRAC_PI_2, 2.0),
        (1e-6, 1.4, -3.0),
    ];
    if (g as usize) < hard.len() {
        let (a, b, c) = hard[g as usize];
        return Angles::new(a, b, c).unwrap_or_else(|_| unreachable!());
    }
    let t = g as f64;
    let ti = FRAC_PI_2 * ((t * 0.618_033_988_75) % 1.0);
    let ts = FRAC_PI_2 * ((t * 0.414_213_562_37) % 1.0);
    let ps = PI * (2.0 * ((t * 0.732_050_807_57) % 1.0) - 1.0);
    Angles::new(ti, ts, ps).unwrap_or_else(|_| unreachable!())
}

fn params(j: u32) -> Params {
    let v = [
        (0.12, 0.01, 1.3, 0.0),
        (0.52, 0.39, 1.42, 0.17),
        (4.04, 1.0, 1.5, 1.0),
        (1e-3, 0.5, 1.0, 0.5),
        (1e3, 0.0, 2.5, 0.9),
        (1.48, 0.73, 1.44, 0.05),
    ][j as usize];
    Params::new(v.0, v.1, v.2, v.3).unwrap_or_else(|_| unreachable!())
}

struct Index {
    g: u32,
    p: u32,
    corr: Correlation,
    out: u32,
}

fn decode(i: u32) -> Index {
    let r = i % PER_GEOMETRY;
    Index {
        g: i / PER_GEOMETRY,
        p: r / (2 * OUTPUTS),
        corr: if (r / OUTPUTS) & 1 == 0 {
            Correlation::Gaussian
        } else {
            Correlation::Exponential
        },
        out: r % OUTPUTS,
    }
}

/// The output of one lane type for every lane, as one lane vector.
fn eval<L: Lane>(ix: &Index, angles_of_lane: impl Fn(usize) -> Angles + Copy) -> L {
    let p = params(ix.p);
    let sigma = [0.0, 0.3, 1.0, 0.5, 0.05, 0.8][ix.p as usize];
    let rho = [0.02, 0.5, 1.0, 0.3, 0.9, 0.7][ix.p as usize];
    match ix.out {
        0..=6 => components(&Geometry::<L>::from_lanes(angles_of_lane), ix.corr, &p).to_array()
            [ix.out as usize],
        7 => {
            let k = JensenCoefficients::<L::Scalar>::new(p.beta().max(0.01), p.a().max(0.01))
                .unwrap_or_else(|_| unreachable!());
            jensen_radiance(&JensenGeometry::<L>::from_lanes(angles_of_lane), &k)
        }
        _ => {
            let k = OrenNayarCoefficients::<L::Scalar>::new(sigma, rho)
                .unwrap_or_else(|_| unreachable!());
            oren_nayar_radiance(&OrenNayarGeometry::<L>::from_lanes(angles_of_lane), &k)
        }
    }
}

/// Value `i` from the `f32x8` path (lane `g % 8` of the vector holding
/// geometries `8⌊g/8⌋ … 8⌊g/8⌋ + 7`), as bits.
pub fn value_f32x8(i: u32) -> u32 {
    let ix = decode(i);
    let base = ix.g / 8 * 8;
    let v: f32x8 = eval(&ix, move |l| angles(base + l as u32));
    v.lane((ix.g % 8) as usize).to_bits()
}

/// Value `i` from the scalar `f32` path, as bits.
pub fn value_f32(i: u32) -> u32 {
    let ix = decode(i);
    let g = ix.g;
    eval::<f32>(&ix, move |_| angles(g)).to_bits()
}

/// Value `i` from the scalar `f64` path, as bits.
pub fn value_f64(i: u32) -> u64 {
    let ix = decode(i);
    let g = ix.g;
    eval::<f64>(&ix, move |_| angles(g)).to_bits()
}
