//! `fit_joint`: one fit across a material's channels.

use crate::convert::{parse, value_error};
use crate::fit_result::{fitter, refine_threads, whole_or, Named};
use crate::measurements::Measurements;
use laminar_brdf_fit::analysis::{DEFAULT_FOLDS, DEFAULT_RESAMPLES};
use laminar_brdf_fit::noise::DEFAULT_FLOOR;
use laminar_brdf_fit::{ChannelTest, JointValue, Model};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::HashMap;

/// A value and its intervals as a dict (`value`, `lo68`, `hi68`, `lo95`,
/// `hi95`, `open_below`, `open_above`; the ends None without a bootstrap).
fn value<'py>(py: Python<'py>, v: &JointValue) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("value", v.value)?;
    let [i68, i95] = v
        .intervals
        .map_or([None, None], |[a, b]| [Some(a), Some(b)]);
    out.set_item("lo68", i68.map(|i| i.lo))?;
    out.set_item("hi68", i68.map(|i| i.hi))?;
    out.set_item("lo95", i95.map(|i| i.lo))?;
    out.set_item("hi95", i95.map(|i| i.hi))?;
    out.set_item("open_below", i95.is_some_and(|i| i.open_below))?;
    out.set_item("open_above", i95.is_some_and(|i| i.open_above))?;
    Ok(out)
}

/// A test of one value for every channel as a dict: ``p_value``,
/// ``statistic``, ``df``; or ``untested`` saying why (and ``channels`` at a
/// face).
fn channel_test<'py>(py: Python<'py>, test: &ChannelTest) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    match test {
        ChannelTest::Tested {
            statistic,
            df1,
            df2,
            p_value,
        } => {
            out.set_item("p_value", p_value)?;
            out.set_item("statistic", statistic)?;
            out.set_item("df", (df1, df2))?;
        }
        ChannelTest::AtAFace(channels) => {
            out.set_item("untested", "on a face of its box")?;
            out.set_item("channels", channels)?;
        }
        ChannelTest::Untestable(why) => out.set_item("untested", why)?,
    }
    Ok(out)
}

/// Fits one layered `model` (default ``exp2``) across the channels
/// ``measurements`` (a sequence of ``Measurements`` of one sample on one
/// geometry): σ/T, σ′/T′ and n shared, a, β and the amplitude per channel,
/// as ``laminar fit-joint``. Returns a dict: ``model``, ``shared`` (each
/// shared parameter's name to its ``value``, ``lo68``, ``hi68``, ``lo95``,
/// ``hi95``: the pairs bootstrap's percentile intervals, and
/// ``open_below``/``open_above``), ``channels`` (per channel: ``channel``,
/// ``a`` as the shared ones, ``beta``, ``amplitude``, ``data_scale``,
/// ``sse``, ``adequacy``: ``chi2_p``, ``runs_p``, ``lack_of_fit``;
/// ``cross_validation``: ``folds``, ``rms`` on held-out geometries and
/// ``in_sample``, or None with ``folds=0``), ``sse`` (their sum),
/// ``measurements``, ``parameters``,
/// ``resamples``, ``chromatic`` (the test of one a for every channel:
/// ``p_value``, ``statistic``, ``df``; or ``untested`` saying why) and
/// ``shared_roughness`` (the test of one σ/T for every channel, untied
/// models, likewise), and ``variants`` (the ways of fitting the channels
/// ranked by AICc over all of them, one noise scale: per variant
/// ``variant`` — ``joint``, ``roughness_per_channel`` (untied models) or
/// ``separate`` —, ``sse``, ``parameters``, ``aicc``, ``rank``, ``delta``
/// and ``weight``).
#[pyfunction]
#[pyo3(signature = (measurements, model = "exp2", grid = None, uncertainty = "both", threads = None, resamples = None, seed = None, precision = "f64", noise = "given", noise_floor = DEFAULT_FLOOR, folds = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit_joint<'py>(
    py: Python<'py>,
    measurements: Bound<'py, PyAny>,
    model: &str,
    grid: Option<HashMap<String, Bound<'py, PyAny>>>,
    uncertainty: &str,
    threads: Option<Bound<'py, PyAny>>,
    resamples: Option<Bound<'py, PyAny>>,
    seed: Option<Bound<'py, PyAny>>,
    precision: &str,
    noise: &str,
    noise_floor: f64,
    folds: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model: Model = parse("model", model)?;
    let not_a_sequence =
        || PyTypeError::new_err("measurements: give a sequence of Measurements, one per channel");
    let scenes = measurements
        .try_iter()
        .map_err(|_| not_a_sequence())?
        .map(|m| {
            let m = m?;
            let m = m.cast::<Measurements>().map_err(|_| not_a_sequence())?;
            m.borrow().scene()
        })
        .collect::<PyResult<Vec<_>>>()?;
    let (_, threads) = refine_threads(None, threads.as_ref())?;
    let named = Named {
        objective: "free",
        uncertainty,
        precision,
        resamples: whole_or("resamples", resamples.as_ref(), DEFAULT_RESAMPLES as u64)?,
        seed: whole_or("seed", seed.as_ref(), 0)?,
        folds: whole_or("folds", folds.as_ref(), DEFAULT_FOLDS as u64)?,
        noise,
        noise_floor,
    };
    let fitter = fitter(grid, threads, true, named)?;
    let fit = py
        .detach(|| fitter.fit_joint(&scenes, model))
        .map_err(value_error)?;
    let out = PyDict::new(py);
    out.set_item("sample", &fit.sample)?;
    out.set_item("model", fit.model.name())?;
    let shared = PyDict::new(py);
    for v in &fit.shared {
        shared.set_item(v.name.name(), value(py, v)?)?;
    }
    out.set_item("shared", shared)?;
    let channels = fit
        .channels
        .iter()
        .map(|c| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("channel", &c.channel)?;
            d.set_item("a", c.a.as_ref().map(|a| value(py, a)).transpose()?)?;
            d.set_item("beta", c.beta)?;
            d.set_item("amplitude", c.amplitude)?;
            d.set_item("data_scale", c.data_scale)?;
            d.set_item("sse", c.sse)?;
            let adequacy = PyDict::new(py);
            adequacy.set_item("chi2_p", c.adequacy.chi2_p)?;
            adequacy.set_item("runs_p", c.adequacy.runs_p)?;
            adequacy.set_item("lack_of_fit", c.adequacy.lack_of_fit)?;
            d.set_item("adequacy", adequacy)?;
            let validated = c
                .cross_validation
                .map(|cv| -> PyResult<Bound<'py, PyDict>> {
                    let v = PyDict::new(py);
                    v.set_item("folds", cv.folds)?;
                    v.set_item("rms", cv.rms)?;
                    v.set_item("in_sample", cv.in_sample)?;
                    Ok(v)
                })
                .transpose()?;
            d.set_item("cross_validation", validated)?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("channels", channels)?;
    out.set_item("sse", fit.sse)?;
    out.set_item("measurements", fit.measurements)?;
    out.set_item("parameters", fit.parameter_count)?;
    out.set_item("resamples", fit.resamples)?;
    out.set_item("chromatic", channel_test(py, &fit.chromatic)?)?;
    out.set_item("shared_roughness", channel_test(py, &fit.shared_roughness)?)?;
    let variants = (fit.variants.iter())
        .map(|v| -> PyResult<Bound<'py, PyDict>> {
            let d = PyDict::new(py);
            d.set_item("variant", v.variant.name())?;
            d.set_item("sse", v.sse)?;
            d.set_item("parameters", v.parameters)?;
            d.set_item("aicc", v.information.and_then(|i| i.aicc))?;
            d.set_item("rank", v.rank.map(|r| r.rank))?;
            d.set_item("delta", v.rank.map(|r| r.delta))?;
            d.set_item("weight", v.rank.map(|r| r.weight))?;
            Ok(d)
        })
        .collect::<PyResult<Vec<_>>>()?;
    out.set_item("variants", variants)?;
    Ok(out)
}
