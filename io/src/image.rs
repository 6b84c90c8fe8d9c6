//! Images: an 8-bit RGB PNG (the `png` crate), written whole or not at all.

use crate::error::ReadError;
use crate::staging::AtomicFile;
use std::path::Path;

/// Writes `rgb` (`width × height` pixels, row-major from the top, three
/// bytes each) to `path` as a PNG, whole or not at all.
///
/// # Errors
/// [`ReadError::Io`] when the file cannot be written, or `rgb` is not
/// `width × height × 3` bytes.
pub fn write_png(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), ReadError> {
    let io = |e: std::io::Error| ReadError::io(path, "write", e);
    let expected = width as usize * height as usize * 3;
    if rgb.len() != expected {
        return Err(io(std::io::Error::other(format!(
            "{} bytes of pixels for a {width} × {height} RGB image ({expected} needed)",
            rgb.len()
        ))));
    }
    let mut file = AtomicFile::create(path)?;
    {
        let mut encoder = png::Encoder::new(&mut file, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut writer = encoder
            .write_header()
            .map_err(|e| io(std::io::Error::other(e)))?;
        writer
            .write_image_data(rgb)
            .map_err(|e| io(std::io::Error::other(e)))?;
        writer.finish().map_err(|e| io(std::io::Error::other(e)))?;
    }
    file.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_png_round_trips_and_a_wrong_size_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("x.png");
        let rgb: Vec<u8> = (0..4 * 3 * 3).map(|i| (i * 7) as u8).collect();
        write_png(&path, 4, 3, &rgb).unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (4, 3));
        assert_eq!(&buf[..info.buffer_size()], &rgb[..]);
        let e = write_png(&dir.path().join("y.png"), 4, 4, &rgb).unwrap_err();
        assert!(e.to_string().contains("y.png"), "{e}");
        assert!(!dir.path().join("y.png").exists());
    }
}
