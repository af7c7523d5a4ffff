//! PNG encoding: true colour (exact) or with a palette of at most 256 colours (smaller files,
//! for pictures kept in a repository). Both are deterministic: the same picture always gives
//! the same bytes.

use anyhow::{Context, Result};
use image::RgbImage;

/// How the pixels are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PngColors {
    /// 8-bit RGB: every colour exact.
    TrueColor,
    /// At most 256 colours: exact when the picture has no more; otherwise a palette fitted by
    /// NeuQuant (colours approximated, typically invisibly; files about a third the size).
    Indexed,
}

/// Encodes `picture` as a PNG file's bytes.
pub fn encode_png(picture: &RgbImage, colors: PngColors) -> Result<Vec<u8>> {
    match colors {
        PngColors::TrueColor => encode_true_color(picture),
        PngColors::Indexed => {
            let (palette, indices) = index_colors(picture);
            encode_indexed(picture.width(), picture.height(), &palette, &indices)
        }
    }
}

fn encode_true_color(picture: &RgbImage) -> Result<Vec<u8>> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder;
    let mut bytes = Vec::new();
    PngEncoder::new_with_quality(&mut bytes, CompressionType::Best, FilterType::Adaptive)
        .write_image(
            picture.as_raw(),
            picture.width(),
            picture.height(),
            image::ExtendedColorType::Rgb8,
        )
        .context("cannot encode the PNG")?;
    Ok(bytes)
}

/// A palette (RGB triples, at most 256) and each pixel's index into it.
fn index_colors(picture: &RgbImage) -> (Vec<[u8; 3]>, Vec<u8>) {
    let mut distinct: Vec<[u8; 3]> = picture.pixels().map(|p| p.0).collect();
    distinct.sort_unstable();
    distinct.dedup();
    if distinct.len() <= 256 {
        let indices = picture
            .pixels()
            .map(|p| distinct.binary_search(&p.0).map_or(0, |i| i as u8))
            .collect();
        return (distinct, indices);
    }
    let rgba: Vec<u8> = picture
        .pixels()
        .flat_map(|p| [p.0[0], p.0[1], p.0[2], 255])
        .collect();
    let quantizer = color_quant::NeuQuant::new(10, 256, &rgba);
    let palette = quantizer
        .color_map_rgb()
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let indices = rgba
        .chunks_exact(4)
        .map(|p| quantizer.index_of(p) as u8)
        .collect();
    (palette, indices)
}

fn encode_indexed(width: u32, height: u32, palette: &[[u8; 3]], indices: &[u8]) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_palette(palette.concat());
    encoder.set_compression(png::Compression::High);
    let mut writer = encoder
        .write_header()
        .context("cannot encode the PNG header")?;
    writer
        .write_image_data(indices)
        .context("cannot encode the PNG")?;
    writer.finish().context("cannot finish the PNG")?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decode(bytes: &[u8]) -> RgbImage {
        image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
            .unwrap()
            .to_rgb8()
    }

    #[test]
    fn few_colours_round_trip_exactly_in_both_modes() {
        let picture =
            RgbImage::from_fn(7, 5, |x, y| image::Rgb([(x * 30) as u8, (y * 50) as u8, 9]));
        for mode in [PngColors::TrueColor, PngColors::Indexed] {
            let bytes = encode_png(&picture, mode).unwrap();
            assert_eq!(decode(&bytes), picture, "{mode:?}");
            assert_eq!(encode_png(&picture, mode).unwrap(), bytes, "deterministic");
        }
        let one = RgbImage::from_pixel(1, 1, image::Rgb([1, 2, 3]));
        assert_eq!(decode(&encode_png(&one, PngColors::Indexed).unwrap()), one);
    }

    #[test]
    fn many_colours_are_approximated_closely() {
        let picture = RgbImage::from_fn(64, 64, |x, y| {
            image::Rgb([(x * 4) as u8, (y * 4) as u8, ((x + y) * 2) as u8])
        });
        let bytes = encode_png(&picture, PngColors::Indexed).unwrap();
        let back = decode(&bytes);
        assert_eq!(back.dimensions(), (64, 64));
        let errors: Vec<i32> = picture
            .pixels()
            .zip(back.pixels())
            .flat_map(|(a, b)| (0..3).map(move |k| (i32::from(a.0[k]) - i32::from(b.0[k])).abs()))
            .collect();
        // 4096 colours spread over the cube, fitted by 256: small errors on average.
        let mean = f64::from(errors.iter().sum::<i32>()) / errors.len() as f64;
        assert!(mean < 8.0, "mean error {mean}");
        assert!(errors.iter().all(|&e| e <= 48), "{:?}", errors.iter().max());
        assert_eq!(encode_png(&picture, PngColors::Indexed).unwrap(), bytes);
    }
}
