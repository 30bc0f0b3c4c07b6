//! Environment maps from files: Radiance RGBE (`.hdr`, `.pic`) and OpenEXR (`.exr`), decoded by the
//! `image` crate (image-rs: its `hdr` and `exr` decoders, the latter the pure-Rust `exr` crate), which
//! refuse corrupt and truncated files with an error and bound what they allocate.

use std::path::Path;

use glam::Vec3;

use super::{Environment, MAX_ENVIRONMENT_SIDE};
use crate::RasterError;

/// Largest file read (1 GiB: a 16384 × 8192 float RGBA EXR is 2 GiB uncompressed, far beyond any map a
/// renderer needs; the decoders' own allocation limit applies too).
pub const MAX_ENVIRONMENT_FILE_BYTES: u64 = 1 << 30;

/// The formats by extension.
fn format_of(path: &str) -> Result<image::ImageFormat, RasterError> {
    let ext = Path::new(path).extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    match ext.as_str() {
        "hdr" | "pic" => Ok(image::ImageFormat::Hdr),
        "exr" => Ok(image::ImageFormat::OpenExr),
        _ => Err(RasterError::File {
            path: path.to_string(),
            problem: format!("unknown extension {ext:?}; expected .hdr (Radiance RGBE) or .exr (OpenEXR)"),
        }),
    }
}

/// An environment from the bytes of a `.hdr` or `.exr` file (`name` names it in errors and gives the
/// format by its extension).
pub fn load_bytes(name: &str, bytes: &[u8]) -> Result<Environment, RasterError> {
    let format = format_of(name)?;
    let file_err = |problem: String| RasterError::File { path: name.to_string(), problem };
    let decode_err = |e: image::ImageError| file_err(format!("cannot decode: {e}"));
    let mut reader = image::ImageReader::with_format(std::io::Cursor::new(bytes), format);
    // The header first: a size beyond the map's limit is refused before any pixel is decoded (a 2 KB
    // EXR declaring 4 × 8388610 texels took 0.75 s and 790 MB to be refused after decoding; found by
    // brdf-fuzz).
    let side = MAX_ENVIRONMENT_SIDE as u32;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(side);
    limits.max_image_height = Some(side);
    reader.limits(limits);
    let decoder = reader.into_decoder().map_err(decode_err)?;
    let (w, h) = image::ImageDecoder::dimensions(&decoder);
    if !(1..=side).contains(&w) || !(1..=side).contains(&h) {
        return Err(file_err(format!("image: must be 1..={side} pixels wide and tall, got {w}×{h}")));
    }
    let img = image::DynamicImage::from_decoder(decoder).map_err(decode_err)?;
    let rgb = img.into_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    Environment::from_rgb(h, w, 3, rgb.as_raw()).map_err(|e| file_err(e.to_string()))
}

/// An environment from a `.hdr` or `.exr` file.
pub fn load(path: &Path) -> Result<Environment, RasterError> {
    let name = path.display().to_string();
    let file_err = |problem: String| RasterError::File { path: name.clone(), problem };
    format_of(&name)?;
    let meta = std::fs::metadata(path).map_err(|e| file_err(e.to_string()))?;
    if meta.len() > MAX_ENVIRONMENT_FILE_BYTES {
        return Err(file_err(format!(
            "is {} bytes, more than the limit of {MAX_ENVIRONMENT_FILE_BYTES}",
            meta.len()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| file_err(e.to_string()))?;
    load_bytes(&name, &bytes)
}

/// A `width × height` linear RGB image (row-major from the top) as the bytes of an OpenEXR file (32-bit
/// float RGB, through the same `image` crate).
pub fn encode_exr(width: usize, height: usize, pixels: &[Vec3]) -> Result<Vec<u8>, RasterError> {
    let data: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
    let buf = image::Rgb32FImage::from_raw(width as u32, height as u32, data)
        .ok_or_else(|| RasterError::arg("image", "the pixel count does not match the size"))?;
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb32F(buf)
        .write_to(&mut out, image::ImageFormat::OpenExr)
        .map_err(|e| RasterError::arg("image", format!("cannot encode OpenEXR: {e}")))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgbe_and_exr_files_round_trip_and_corrupt_ones_are_refused_naming_the_file() {
        let px: Vec<Vec3> = (0..8 * 4).map(|i| Vec3::new(i as f32 * 0.5, 1.0, 1e-3 * i as f32)).collect();
        let env = load_bytes("a.hdr", &super::super::rgbe::encode(8, 4, &px)).unwrap();
        assert_eq!(env.map.size(), (8, 4));
        for (a, b) in env.map.texels().iter().zip(&px) {
            assert!((*a - *b).abs().max_element() <= b.max_element() / 100.0 + 1e-6, "{a} vs {b}");
        }
        let exr = encode_exr(8, 4, &px).unwrap();
        let env = load_bytes("a.exr", &exr).unwrap();
        assert_eq!(env.map.texels(), &px[..]);
        let bad = load_bytes("broken.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n\x01\x02")
            .unwrap_err();
        assert!(bad.to_string().starts_with("broken.hdr:"), "{bad}");
        assert!(
            load_bytes("broken.exr", &exr[..exr.len() / 2])
                .unwrap_err()
                .to_string()
                .starts_with("broken.exr:")
        );
        assert!(load_bytes("x.png", &exr).unwrap_err().to_string().contains("unknown extension"));
    }
}
