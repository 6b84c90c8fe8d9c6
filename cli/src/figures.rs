//! SVG figures: the Fig. 2 transmission/absorption curves, the normalised
//! data-against-model plots of Figs. 3–4 and the parameters' profiles,
//! drawn with `plotters`.

use laminar_brdf_core::energy_budget;
use laminar_brdf_fit::profile::{DELTA_68, DELTA_95};
use laminar_brdf_fit::ProfileCurve;
use plotters::prelude::*;

/// Absorption values drawn in Fig. 2.
pub const FIG2_ABSORPTION: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
/// Refractive index of Fig. 2.
pub const FIG2_N: f64 = 1.7;

fn failed(e: impl std::fmt::Display) -> String {
    format!("drawing failed: {e}")
}

/// Fig. 2: transmission `T` (solid) and absorption `A` (dashed) against the
/// incidence angle for n = 1.7 and each a of [`FIG2_ABSORPTION`] (eq. 9).
///
/// # Errors
/// The drawing backend's message when the SVG cannot be drawn.
pub fn energy_budget_svg() -> Result<String, String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (820, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(failed)?;
        // The key goes beside the plot: inside, it would hide the curves,
        // which fill the whole range.
        let (plot, key) = root.split_horizontally(700);
        let mut chart = ChartBuilder::on(&plot)
            .caption(
                format!("Transmission and absorption, n = {FIG2_N}"),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..90.0, 0.0..1.0)
            .map_err(failed)?;
        chart
            .configure_mesh()
            .x_desc("incidence angle θ (degrees)")
            .y_desc("fraction of incident energy")
            .draw()
            .map_err(failed)?;
        let angles: Vec<f64> = (0..=180).map(|i| i as f64 * 0.5).collect();
        let text = ("sans-serif", 13).into_font();
        for (i, &a) in FIG2_ABSORPTION.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let budget = |deg: f64| energy_budget(deg.to_radians().cos(), FIG2_N, a);
            chart
                .draw_series(LineSeries::new(
                    angles.iter().map(|&d| (d, budget(d).transmitted)),
                    colour.stroke_width(2),
                ))
                .map_err(failed)?;
            chart
                .draw_series(DashedLineSeries::new(
                    angles.iter().map(|&d| (d, budget(d).absorbed)),
                    6,
                    4,
                    colour.stroke_width(2),
                ))
                .map_err(failed)?;
            for (j, name) in ["T", "A"].into_iter().enumerate() {
                let y = 60 + 22 * (2 * i + j) as i32;
                let segments: &[(i32, i32)] = if j == 0 {
                    &[(0, 24)]
                } else {
                    &[(0, 8), (14, 24)]
                };
                for &(x0, x1) in segments {
                    key.draw(&PathElement::new(
                        [(4 + x0, y), (4 + x1, y)],
                        colour.stroke_width(2),
                    ))
                    .map_err(failed)?;
                }
                key.draw(&Text::new(
                    format!("{name}, a = {a}"),
                    (34, y - 7),
                    text.clone(),
                ))
                .map_err(failed)?;
            }
        }
        root.present().map_err(failed)?;
    }
    Ok(svg)
}

/// Figs. 3–4 style: normalised measured radiance (x) against the model's
/// normalised prediction (y), one point per kept measurement, with the line
/// y = x of a perfect fit.
///
/// # Errors
/// The drawing backend's message when the SVG cannot be drawn.
pub fn data_vs_model_svg(title: &str, data: &[f64], model: &[f64]) -> Result<String, String> {
    let top = data
        .iter()
        .chain(model)
        .fold(1.0_f64, |m, &v| if v.is_finite() { m.max(v) } else { m });
    let low = data.iter().chain(model).fold(0.0_f64, |m, &v| m.min(v));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (520, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(failed)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(low..top * 1.02, low..top * 1.02)
            .map_err(failed)?;
        chart
            .configure_mesh()
            .x_desc("normalised measured radiance")
            .y_desc("normalised model radiance")
            .draw()
            .map_err(failed)?;
        chart
            .draw_series(LineSeries::new([(low, low), (top, top)], BLACK.mix(0.5)))
            .map_err(failed)?;
        chart
            .draw_series(
                data.iter()
                    .zip(model)
                    .map(|(&d, &p)| Circle::new((d, p), 3, BLUE.filled())),
            )
            .map_err(failed)?;
        root.present().map_err(failed)?;
    }
    Ok(svg)
}

/// A parameter's profile on the Δχ² scale: the continuous profile (line),
/// the grid's profile at its axis values (points), the refined estimate
/// (vertical line), and the 68% and 95% levels (dashed), whose crossings
/// with the line are the interval ends.
///
/// # Errors
/// The drawing backend's message when the SVG cannot be drawn.
pub fn profile_svg(title: &str, curve: &ProfileCurve) -> Result<String, String> {
    let xs = curve.refined.iter().chain(&curve.grid).map(|p| p.0);
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let (x0, x1) = if x1 > x0 {
        (x0, x1)
    } else {
        (x0 - 1e-3, x0 + 1e-3)
    };
    let top = 3.0 * DELTA_95;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (560, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(failed)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 17))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(x0..x1, 0.0..top)
            .map_err(failed)?;
        chart
            .configure_mesh()
            .x_desc(format!("{} (fixed)", curve.name))
            .y_desc("Δχ² = (min over the others − minimum) / s²")
            .draw()
            .map_err(failed)?;
        for (level, label) in [(DELTA_68, "68%"), (DELTA_95, "95%")] {
            chart
                .draw_series(DashedLineSeries::new(
                    [(x0, level), (x1, level)],
                    6,
                    4,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(failed)?
                .label(format!("{label} level"))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], BLACK.mix(0.5)));
        }
        chart
            .draw_series(DashedLineSeries::new(
                [(curve.estimate, 0.0), (curve.estimate, top)],
                3,
                3,
                RED.stroke_width(1),
            ))
            .map_err(failed)?
            .label("refined estimate")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], RED));
        let clip = |v: f64| v.min(top);
        chart
            .draw_series(LineSeries::new(
                curve.refined.iter().map(|&(x, y)| (x, clip(y))),
                BLUE.stroke_width(2),
            ))
            .map_err(failed)?
            .label("profile, others refined")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], BLUE.stroke_width(2)));
        chart
            .draw_series(
                curve
                    .grid
                    .iter()
                    .filter(|p| p.1 <= top)
                    .map(|&(x, y)| Circle::new((x, y), 4, BLACK.filled())),
            )
            .map_err(failed)?
            .label("profile on the grid")
            .legend(|(x, y)| Circle::new((x + 9, y), 4, BLACK.filled()));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(failed)?;
        root.present().map_err(failed)?;
    }
    Ok(svg)
}

/// One channel of a spectrum: where it sits on the x axis, a value and its
/// 68% and 95% intervals (none without a bootstrap).
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumPoint {
    /// The wavelength (nm), or the channel's index.
    pub x: f64,
    /// The value.
    pub value: f64,
    /// `[(lo68, hi68), (lo95, hi95)]`.
    pub bands: Option<[(f64, f64); 2]>,
}

/// A spectrum across a material's channels: one panel per named series
/// (`a(λ)`, `β(λ)`, each in [0, 1]), each the values as a line with
/// points and, where given, the 68% band (darker) inside the 95% band
/// (lighter). `x_desc` names the x axis; `x_names`, when not empty, label
/// the channels at x = 0, 1, … (else x is a wavelength).
///
/// # Errors
/// The drawing backend's message when the SVG cannot be drawn.
pub fn spectrum_svg(
    title: &str,
    (x_desc, x_names): (&str, &[String]),
    series: &[(&str, Vec<SpectrumPoint>)],
) -> Result<String, String> {
    let x_label = |x: &f64| {
        if x_names.is_empty() {
            return format!("{x:.0}");
        }
        let i = x.round();
        let name = (i >= 0.0 && (x - i).abs() < 1e-6).then(|| x_names.get(i as usize));
        name.flatten().cloned().unwrap_or_default()
    };
    let xs = series
        .iter()
        .flat_map(|(_, points)| points.iter().map(|p| p.x));
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = ((x1 - x0) * 0.03).max(0.5);
    let (x0, x1) = (x0 - pad, x1 + pad);
    let mut svg = String::new();
    {
        let height = 60 + 300 * series.len() as u32;
        let root = SVGBackend::with_string(&mut svg, (720, height)).into_drawing_area();
        root.fill(&WHITE).map_err(failed)?;
        let root = root.titled(title, ("sans-serif", 18)).map_err(failed)?;
        for ((name, points), area) in series.iter().zip(root.split_evenly((series.len(), 1))) {
            let top = points
                .iter()
                .flat_map(|p| {
                    let ends = p.bands.map_or([p.value; 2], |[_, (_, hi)]| [hi, p.value]);
                    ends.into_iter()
                })
                .fold(1.0_f64, f64::max);
            let mut chart = ChartBuilder::on(&area)
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(56)
                .build_cartesian_2d(x0..x1, 0.0..top * 1.02)
                .map_err(failed)?;
            chart
                .configure_mesh()
                .x_desc(x_desc)
                .y_desc(*name)
                .x_label_formatter(&x_label)
                .light_line_style(BLACK.mix(0.04))
                .draw()
                .map_err(failed)?;
            for (level, shade) in [(1, 0.15), (0, 0.3)] {
                let banded: Vec<&SpectrumPoint> =
                    points.iter().filter(|p| p.bands.is_some()).collect();
                if banded.len() < 2 {
                    continue;
                }
                let band = |p: &SpectrumPoint| p.bands.map_or((p.value, p.value), |b| b[level]);
                let outline: Vec<(f64, f64)> = (banded.iter().map(|p| (p.x, band(p).0)))
                    .chain(banded.iter().rev().map(|p| (p.x, band(p).1)))
                    .collect();
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        outline,
                        BLUE.mix(shade).filled(),
                    )))
                    .map_err(failed)?
                    .label(if level == 0 {
                        "68% interval"
                    } else {
                        "95% interval"
                    })
                    .legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 18, y + 5)], BLUE.mix(shade).filled())
                    });
            }
            chart
                .draw_series(LineSeries::new(
                    points.iter().map(|p| (p.x, p.value)),
                    BLUE.stroke_width(2),
                ))
                .map_err(failed)?
                .label("estimate")
                .legend(|(x, y)| PathElement::new([(x, y), (x + 18, y)], BLUE.stroke_width(2)));
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|p| Circle::new((p.x, p.value), 3, BLUE.filled())),
                )
                .map_err(failed)?;
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(failed)?;
        }
        root.present().map_err(failed)?;
    }
    Ok(svg)
}

/// Data against model per channel: one small log–log panel per channel
/// (`(name, data, model)`, both normalised), the points whose data and
/// prediction are positive, with the line y = x of a perfect fit; a panel
/// says how many points it leaves out.
///
/// # Errors
/// The drawing backend's message when the SVG cannot be drawn.
pub fn channels_vs_model_svg(
    title: &str,
    panels: &[(String, Vec<f64>, Vec<f64>)],
) -> Result<String, String> {
    let columns = (panels.len() as f64).sqrt().ceil().max(1.0) as usize;
    let rows = panels.len().div_ceil(columns).max(1);
    let mut svg = String::new();
    {
        let (w, h) = (250 * columns as u32, 40 + 250 * rows as u32);
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(failed)?;
        let root = root.titled(title, ("sans-serif", 18)).map_err(failed)?;
        for ((name, data, model), area) in panels.iter().zip(root.split_evenly((rows, columns))) {
            let points: Vec<(f64, f64)> = (data.iter().zip(model))
                .filter(|(d, p)| **d > 0.0 && **p > 0.0 && d.is_finite() && p.is_finite())
                .map(|(&d, &p)| (d, p))
                .collect();
            let (lo, hi) = points
                .iter()
                .fold((f64::INFINITY, 0.0_f64), |(lo, hi), &(d, p)| {
                    (lo.min(d).min(p), hi.max(d).max(p))
                });
            let (lo, hi) = if lo < hi {
                (lo / 1.5, hi * 1.5)
            } else {
                (1e-3, 1.0)
            };
            let left_out = data.len() - points.len();
            let caption = if left_out > 0 {
                format!("{name} ({left_out} ≤ 0 left out)")
            } else {
                name.clone()
            };
            let mut chart = ChartBuilder::on(&area)
                .caption(caption, ("sans-serif", 13))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(42)
                .build_cartesian_2d((lo..hi).log_scale(), (lo..hi).log_scale())
                .map_err(failed)?;
            chart
                .configure_mesh()
                .x_labels(4)
                .y_labels(4)
                .x_label_formatter(&|x| format!("{x:.0e}"))
                .y_label_formatter(&|y| format!("{y:.0e}"))
                .x_desc("data")
                .y_desc("model")
                .light_line_style(BLACK.mix(0.04))
                .draw()
                .map_err(failed)?;
            chart
                .draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.mix(0.5)))
                .map_err(failed)?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&p| Circle::new(p, 1, BLUE.mix(0.5).filled())),
                )
                .map_err(failed)?;
        }
        root.present().map_err(failed)?;
    }
    Ok(svg)
}
