//! The cases of the wasm parity probe, shared by the wasm module
//! (`main.rs`) and the native test (`tests/wasm_parity.rs`).
//!
//! Value `i` is decoded as (geometry, parameter set, correlation, output),
//! outputs being the seven model components plus Jensen and Oren–Nayar.

use laminar_brdf_core::baselines::jensen::{jensen_radiance, JensenCoefficients, JensenGeometry};
use laminar_brdf_core::baselines::oren_nayar::{
    oren_nayar_radiance, OrenNayarCoefficients, OrenNayarGeometry,
};
use laminar_brdf_core::{components, f32x8, probe, Angles, Correlation, Geometry, Lane, Params};

/// Geometries probed (a multiple of 8).
pub const GEOMETRIES: u32 = probe::GEOMETRIES;
const PARAMS: u32 = probe::PARAMS;
const OUTPUTS: u32 = 9;
const PER_GEOMETRY: u32 = PARAMS * 2 * OUTPUTS;

/// Number of probed values.
pub fn count() -> u32 {
    GEOMETRIES * PER_GEOMETRY
}

/// Geometry `g` ([`probe::angles`]).
pub fn angles(g: u32) -> Angles {
    let (theta_i, theta_s, phi_s) = probe::angles(g);
    Angles::new(theta_i, theta_s, phi_s).unwrap_or_else(|_| unreachable!())
}

fn params(j: u32) -> Params {
    let (slope, beta, n, a) = probe::params(j);
    Params::new(slope, beta, n, a).unwrap_or_else(|_| unreachable!())
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
