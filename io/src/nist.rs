//! NIST's Mueller-matrix BRDF CSV files (Germer 2017, sintered PTFE;
//! docs/formats.md, "NIST Mueller-matrix BRDF CSV"):
//!
//! ```text
//! lambda,thetai,phi,thetar,phir,f_r11,f_r12/f_r11,…,f_r44/f_r11
//! 0.351,-0.001,0,80.0258,-156.038,2.62E-01,0.0127079,…
//! ```
//!
//! One row per (wavelength, geometry): `lambda` in micrometres, the angles
//! in degrees, `f_r11` the unpolarised BRDF (sr⁻¹); the normalised Mueller
//! elements after it are not read. Both directions are (polar, azimuth) of
//! vectors pointing away from the sample, the mirror of `(thetai, phi)` at
//! `(thetai, phi + 180°)`; `thetai` is signed, a negative one the polar
//! angle `|thetai|` at azimuth `phi + 180°` (the file's source sits at
//! azimuth 180°, and normal incidence is written −0.001). Each wavelength
//! becomes a channel (`532nm`), and every wavelength must give the same
//! geometries in the same order.

use crate::error::ReadError;
use crate::reader::{brdf_set, contents, number, text};
use laminar_brdf_fit::{MeasurementAngles, MeasurementSet};
use std::path::Path;

/// The columns read, by name.
pub const COLUMNS: [&str; 6] = ["lambda", "thetai", "phi", "thetar", "phir", "f_r11"];

/// Reads a NIST Mueller-matrix BRDF CSV file (module docs) as a set named
/// after the file stem: each wavelength a channel of `f_r11`, on the
/// geometries (lab frame) every wavelength shares; the rows are the
/// first wavelength's line numbers.
///
/// ```
/// # let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("ptfe.csv");
/// std::fs::write(
///     &path,
///     "lambda,thetai,phi,thetar,phir,f_r11,f_r12/f_r11\n\
///      0.532,-30,0,20,10,0.31,0.01\n0.532,-30,0,40,170,0.29,0.02\n\
///      1.064,-30,0,20,10,0.32,0.01\n1.064,-30,0,40,170,0.30,0.02\n",
/// )?;
/// let set = laminar_brdf_io::nist::read_nist(&path)?;
/// assert_eq!(set.channel_names(), ["532nm", "1064nm"]);
/// assert_eq!(set.len(), 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`ReadError`] naming the file, line, column and value: a missing
/// column, a field that is not a number, a wavelength whose geometries are
/// not the first's, or angles outside their domain.
pub fn read_nist(file: &Path) -> Result<MeasurementSet, ReadError> {
    parse_nist(file, &contents(file)?)
}

/// One wavelength's rows: its value (µm, as written), and per row the line,
/// the four angles as written and `f_r11`.
struct Wavelength {
    lambda: f64,
    rows: Vec<(usize, [f64; 4], f64)>,
}

/// [`read_nist`] on contents already in memory (`file` names the set and
/// the errors).
///
/// # Errors
/// As [`read_nist`].
pub fn parse_nist(file: &Path, bytes: &[u8]) -> Result<MeasurementSet, ReadError> {
    let text = text(file, bytes)?;
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim_end_matches('\r')))
        .filter(|(_, l)| !l.trim().is_empty());
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| ReadError::format(file, 0, "empty file: a header line is needed"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let place = COLUMNS.map(|c| names.iter().position(|n| n.eq_ignore_ascii_case(c)));
    if let Some(missing) = COLUMNS.iter().zip(&place).find(|(_, p)| p.is_none()) {
        return Err(ReadError::format(
            file,
            header_line,
            format!(
                "no column `{}`: a NIST BRDF file has the columns {}",
                missing.0,
                COLUMNS.join(",")
            ),
        ));
    }
    let place = place.map(|p| p.unwrap_or(0));
    let mut wavelengths: Vec<Wavelength> = Vec::new();
    for (line, row) in lines {
        let fields: Vec<&str> = row.split(',').collect();
        let value = |c: usize| {
            let field = fields.get(place[c]).copied().unwrap_or("");
            number(file, line, place[c], COLUMNS[c], field)
        };
        let [lambda, thetai, phi, thetar, phir, f] = [0, 1, 2, 3, 4, 5].map(value);
        let lambda = lambda?;
        if lambda <= 0.0 {
            return Err(ReadError::format(
                file,
                line,
                format!(
                    "column {} (lambda): `{lambda}` is not a wavelength (µm)",
                    place[0] + 1
                ),
            ));
        }
        let row = (line, [thetai?, phi?, thetar?, phir?], f?);
        match wavelengths.iter_mut().find(|w| w.lambda == lambda) {
            Some(w) => w.rows.push(row),
            None => wavelengths.push(Wavelength {
                lambda,
                rows: vec![row],
            }),
        }
    }
    let Some(first) = wavelengths.first() else {
        return Err(ReadError::format(file, 0, "no data rows after the header"));
    };
    for w in &wavelengths[1..] {
        same_geometries(file, first, w)?;
    }
    let angles = first.rows.iter().map(|(_, a, _)| lab(*a)).collect();
    let lines = first.rows.iter().map(|(line, _, _)| *line).collect();
    let channels = wavelengths.iter().map(|w| {
        let values = w.rows.iter().map(|(_, _, f)| *f).collect();
        (channel_name(w.lambda), values)
    });
    brdf_set(file, "measurements", angles, Some(lines), channels)
}

/// A wavelength in micrometres as a channel name in nanometres (`532nm`).
fn channel_name(lambda: f64) -> String {
    let nm = lambda * 1000.0;
    if (nm - nm.round()).abs() < 1e-6 {
        format!("{}nm", nm.round())
    } else {
        format!("{nm}nm")
    }
}

/// Refuses a wavelength `w` whose geometries are not `first`'s, in order.
fn same_geometries(file: &Path, first: &Wavelength, w: &Wavelength) -> Result<(), ReadError> {
    if let Some(((line, a, _), (_, b, _))) =
        (w.rows.iter().zip(&first.rows)).find(|(x, y)| x.1 != y.1)
    {
        return Err(ReadError::format(
            file,
            *line,
            format!(
                "wavelength {} µm: geometry {a:?} where wavelength {} µm has {b:?}; \
                 every wavelength must give the same geometries in the same order",
                w.lambda, first.lambda
            ),
        ));
    }
    if w.rows.len() != first.rows.len() {
        let line = w.rows.last().map_or(0, |r| r.0);
        return Err(ReadError::format(
            file,
            line,
            format!(
                "wavelength {} µm has {} geometries, wavelength {} µm {}",
                w.lambda,
                w.rows.len(),
                first.lambda,
                first.rows.len()
            ),
        ));
    }
    Ok(())
}

/// The lab-frame angles (radians) of a row's `thetai, phi, thetar, phir`
/// (degrees): a negative `thetai` is `|thetai|` at azimuth `phi + 180°`.
fn lab([thetai, phi, thetar, phir]: [f64; 4]) -> MeasurementAngles {
    let phi_i = if thetai < 0.0 { phi + 180.0 } else { phi };
    MeasurementAngles::Lab {
        theta_i: thetai.abs().to_radians(),
        phi_i: phi_i.to_radians(),
        theta_v: thetar.to_radians(),
        phi_v: phir.to_radians(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<MeasurementSet, String> {
        parse_nist(Path::new("n.csv"), text.as_bytes()).map_err(|e| e.to_string())
    }

    const GOOD: &str = "lambda,thetai,phi,thetar,phir,f_r11,f_r12/f_r11\r\n\
                        0.351,-30,0,30,6.36E-15,3.26E-01,0.1\r\n0.351,-30,0,40,170,0.29,0.2\r\n\
                        0.633,-30,0,30,6.36E-15,3.30E-01,0.1\r\n0.633,-30,0,40,170,0.31,0.2\r\n";

    #[test]
    fn wavelengths_become_channels_and_a_signed_incidence_turns_round() {
        let set = parse(GOOD).unwrap();
        assert_eq!(set.channel_names(), ["351nm", "633nm"]);
        // θi = −30°, φ = 0: the source at azimuth 180°, so the first row is
        // its mirror direction (left out as specular), the second is not.
        assert_eq!(set.kept(), [1]);
        match set.angles()[0] {
            MeasurementAngles::Lab { theta_i, phi_i, .. } => {
                assert_eq!((theta_i, phi_i), (30f64.to_radians(), 180f64.to_radians()));
            }
            MeasurementAngles::Paper { .. } => panic!("lab frame"),
        }
    }

    #[test]
    fn defects_name_the_line_column_and_value() {
        // Each case: GOOD with `from` replaced by `to`, and the error it gives.
        #[rustfmt::skip]
        let cases = [
            ("f_r11,", "f,", "n.csv:1: no column `f_r11`"),
            ("0.29,", "x,", "n.csv:3: column 6 (f_r11): `x` is not a number"),
            ("0.633,-30,0,40", "0.633,-30,0,41", "n.csv:5: wavelength 0.633 µm: geometry"),
            ("0.633,-30,0,40,170,0.31,0.2\r\n", "", "n.csv:4: wavelength 0.633 µm has 1 geometries"),
            ("0.351,-30,0,30", "-0.351,-30,0,30", "n.csv:2: column 1 (lambda): `-0.351` is not a wavelength"),
            ("0,40,170", "0,95,170", "theta_v"),
        ];
        crate::reader::assert_defects(parse, GOOD, &cases);
        let e = parse("lambda,thetai,phi,thetar,phir,f_r11\n").unwrap_err();
        assert!(e.contains("n.csv: no data rows"), "{e}");
    }
}
