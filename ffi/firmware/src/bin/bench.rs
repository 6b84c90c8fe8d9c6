//! Instruction counts and stack depths of the f32 path on the emulated
//! Cortex-M4F. Run by `ffi/tests/firmware_cost.rs` under QEMU with
//! `-icount shift=0` (one instruction per virtual nanosecond), read from
//! the board's timer ([`laminar_firmware::timer`]); each function runs
//! `REPEATS` times between two reads.
//! These are instructions, not cycles (QEMU does not model the pipeline).
//!
//! Prints `name instructions stack_bytes`, one line per function.

#![no_std]
#![no_main]

use core::hint::black_box;
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};
use laminar_brdf_core::{total_radiance_in, Angles, Correlation, Directions, Geometry, LaneParams};
use laminar_brdf_ffi::{
    laminar_evaluate_f32, laminar_fit, laminar_fit_free, LaminarFitResult, LaminarFitScratch,
    LaminarFreeFitResult, LaminarFreeGrid, LaminarGeometry, LaminarGrid, LaminarParamsF32,
};
use laminar_firmware::{timer, timer_start, INSTRUCTIONS_PER_TICK};

const REPEATS: u32 = 1000;

/// Instructions of `REPEATS` calls of `f`, in tenths per call.
fn instructions(mut f: impl FnMut()) -> u64 {
    let t0 = timer();
    for _ in 0..REPEATS {
        f();
    }
    let t1 = timer();
    (t0.wrapping_sub(t1) as u64) * INSTRUCTIONS_PER_TICK * 10 / REPEATS as u64
}

const PAINT: u32 = 0x5A5A_A5A5;
const PAINTED_WORDS: usize = 2048;

/// Bytes of stack below the caller's frame that one call of `f` touched:
/// the 8 KB below the stack pointer are painted, `f` runs once, and the
/// deepest word that changed marks the depth.
#[allow(unsafe_code)]
fn stack_bytes(f: impl FnOnce()) -> usize {
    let sp = cortex_m::register::msp::read() as usize;
    let top = (sp - 64) & !3;
    let bottom = top - 4 * PAINTED_WORDS;
    // SAFETY: the painted words lie below the stack pointer (with a margin
    // for this function's own calls), in RAM the stack may grow into and
    // that nothing else holds; volatile, so the writes are not elided.
    unsafe {
        for w in 0..PAINTED_WORDS {
            ((bottom + 4 * w) as *mut u32).write_volatile(PAINT);
        }
    }
    f();
    let mut deepest = top;
    for w in (0..PAINTED_WORDS).rev() {
        let addr = bottom + 4 * w;
        // SAFETY: as above.
        if unsafe { (addr as *const u32).read_volatile() } != PAINT {
            deepest = addr;
        }
    }
    sp - deepest
}

fn report(name: &str, per_call_tenths: u64, stack: usize) {
    hprintln!(
        "{} {}.{} {}",
        name,
        per_call_tenths / 10,
        per_call_tenths % 10,
        stack
    );
}

/// Measures `f` (minus the loop's own cost, `empty`) and its stack.
fn bench(name: &str, empty: u64, mut f: impl FnMut()) {
    let count = instructions(&mut f).saturating_sub(empty);
    report(name, count, stack_bytes(f));
}

#[entry]
fn main() -> ! {
    timer_start();
    let empty = instructions(|| {
        black_box(0u32);
    });
    let angles = Angles::new(0.52, 0.91, 2.3).unwrap();
    let g = Geometry::<f32>::splat(&angles);
    let p = LaneParams::<f32>::new(1.48, 0.39, 1.44, 0.17).unwrap();
    for (name, corr) in [
        ("total_radiance_exp", Correlation::Exponential),
        ("total_radiance_gauss", Correlation::Gaussian),
    ] {
        bench(name, empty, || {
            black_box(total_radiance_in(black_box(&g), corr, black_box(&p)));
        });
    }
    let rh = LaneParams::<f32>::new(1.48, 0.39, 1.44, 0.0).unwrap();
    bench("total_radiance_exp_a0", empty, || {
        black_box(total_radiance_in(
            black_box(&g),
            Correlation::Exponential,
            black_box(&rh),
        ));
    });
    let lg = LaminarGeometry::from(g);
    let lp = LaminarParamsF32 {
        slope: 1.48,
        beta: 0.39,
        n: 1.44,
        a: 0.17,
    };
    bench("laminar_evaluate_f32_1", empty, || {
        let mut out = 0.0f32;
        black_box(laminar_evaluate_f32(
            0,
            black_box(lp),
            black_box(&lg),
            1,
            &mut out,
        ));
    });
    bench("geometry_from_angles_f32", empty, || {
        black_box(Geometry::from_angles_f32(
            black_box(0.52),
            black_box(0.91),
            black_box(2.3),
        ))
        .ok();
    });
    let d = Directions {
        cos_i: 0.867_819,
        sin_i: 0.496_880,
        cos_s: 0.613_746,
        sin_s: 0.789_504,
        cos_phi: -0.666_276,
        sin_phi: 0.745_705,
    };
    bench("geometry_from_directions", empty, || {
        black_box(Geometry::from_directions(black_box(&d))).ok();
    });
    bench("geometry_from_angles_f64_trig", empty, || {
        black_box(Geometry::<f32>::splat(black_box(&angles)));
    });
    // The fits at a one-point grid (K = 32): the cost of one grid point
    // with everything a fit sets up, and the whole call's stack (the
    // scratch is the caller's, outside it).
    let (geometry, data) = laminar_brdf_ffi::probe::fit_case(32);
    let mut scratch = LaminarFitScratch::new();
    let (slope, n, a, beta) = ([0.92], [1.42], [0.3], [0.4]);
    bench("laminar_fit_one_point_k32", empty, || {
        let grid = LaminarGrid {
            slope: slope.as_ptr(),
            slope_count: 1,
            n: n.as_ptr(),
            n_count: 1,
            a: a.as_ptr(),
            a_count: 1,
            beta: beta.as_ptr(),
            beta_count: 1,
        };
        let mut out = LaminarFitResult::default();
        black_box(laminar_fit(
            0,
            geometry.as_ptr(),
            black_box(data.as_ptr()),
            32,
            grid,
            &mut scratch,
            &mut out,
        ));
    });
    bench("laminar_fit_free_one_point_k32", empty, || {
        let grid = LaminarFreeGrid {
            slope: slope.as_ptr(),
            slope_count: 1,
            n: n.as_ptr(),
            n_count: 1,
            a: a.as_ptr(),
            a_count: 1,
            beta_lo: 0.0,
            beta_hi: 1.0,
        };
        let mut out = LaminarFreeFitResult::default();
        black_box(laminar_fit_free(
            0,
            geometry.as_ptr(),
            black_box(data.as_ptr()),
            core::ptr::null(),
            32,
            grid,
            &mut scratch,
            &mut out,
        ));
    });
    hprintln!("done");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::wfi(); // not reached: the exit above ends QEMU
    }
}
