//! A title and a legend drawn in a band above the picture, with the embedded font (DejaVu Sans,
//! through plotters, as the bench plots): the mesh is drawn below the band, so nothing covers
//! it. Deterministic: the same text gives the same pixels.

use image::RgbImage;
use plotters::prelude::*;

/// One legend entry: what the colour or line shows.
#[derive(Clone, Debug, PartialEq)]
pub struct LegendEntry {
    /// The swatch's colour.
    pub color: [u8; 3],
    /// A filled square (a colour of triangles) or a line (an outline).
    pub line: bool,
    /// What it means.
    pub label: String,
}

/// Smallest picture (in pixels) that gets a title and a legend; smaller pictures are left
/// as the mesh alone (the text would cover them).
pub const MIN_ANNOTATED: (u32, u32) = (320, 240);

/// Text size in pixels for a picture of width `width`.
fn font_size(width: u32) -> f64 {
    (f64::from(width) / 64.0).clamp(11.0, 28.0).round()
}

/// Lays the entries out in rows that fit in `width`: the rows of entry indices.
fn rows(entries: &[LegendEntry], width: u32, size: f64) -> Vec<Vec<usize>> {
    let (style, pad) = (("sans-serif", size), size * 0.8);
    let mut rows: Vec<Vec<usize>> = vec![Vec::new()];
    let mut x = pad;
    for (i, e) in entries.iter().enumerate() {
        let text = style
            .into_font()
            .box_size(&e.label)
            .map_or(e.label.len() as f64 * size * 0.55, |(w, _)| f64::from(w));
        let w = size * 1.6 + text + pad * 1.5;
        let row = rows.last_mut().expect("one row at least");
        if !row.is_empty() && x + w > f64::from(width) - pad {
            rows.push(vec![i]);
            x = pad + w;
        } else {
            row.push(i);
            x += w;
        }
    }
    rows
}

/// Height of the band a title and `entries` take in a picture of width `width`, or 0 when
/// the picture is smaller than [`MIN_ANNOTATED`] (`height` is the whole picture's).
pub fn band_height(entries: &[LegendEntry], width: u32, height: u32) -> u32 {
    if width < MIN_ANNOTATED.0 || height < MIN_ANNOTATED.1 {
        return 0;
    }
    let size = font_size(width);
    let lines = 1 + rows(entries, width, size).len();
    (size * 0.8 + lines as f64 * size * 1.45) as u32
}

/// Draws `title` and the legend `entries` in the top `band` pixels of `picture` (white
/// there); the fonts are registered by [`crate::plot::register_font`].
pub fn annotate(picture: &mut RgbImage, band: u32, title: &str, entries: &[LegendEntry]) {
    if band == 0 {
        return;
    }
    crate::plot::register_font();
    let (width, height) = picture.dimensions();
    let size = font_size(width);
    let layout = rows(entries, width, size);
    let root = BitMapBackend::with_buffer(picture.as_mut(), (width, height)).into_drawing_area();
    let pad = size * 0.8;
    let text = |s: &str, x: f64, y: f64, px: f64, colour: RGBColor| {
        let style = TextStyle::from(("sans-serif", px).into_font()).color(&colour);
        // Drawing text cannot fail on a bitmap; a missing glyph leaves a gap.
        let _ = root.draw_text(s, &style, (x as i32, y as i32));
    };
    text(title, pad, pad * 0.6, size * 1.1, RGBColor(20, 20, 20));
    for (r, row) in layout.iter().enumerate() {
        let y = pad * 0.6 + (r + 1) as f64 * size * 1.45;
        let mut x = pad;
        for &i in row {
            let e = &entries[i];
            let c = RGBColor(e.color[0], e.color[1], e.color[2]);
            let s = size * 0.9;
            let (x0, y0) = (x as i32, (y + size * 0.1) as i32);
            if e.line {
                let mid = y0 + (s / 2.0) as i32;
                let w = (size / 6.0).max(2.0) as i32;
                let _ = root.draw(&Rectangle::new(
                    [(x0, mid - w / 2), (x0 + s as i32, mid - w / 2 + w)],
                    c.filled(),
                ));
            } else {
                let _ = root.draw(&Rectangle::new(
                    [(x0, y0), (x0 + s as i32, y0 + s as i32)],
                    c.filled(),
                ));
                let _ = root.draw(&Rectangle::new(
                    [(x0, y0), (x0 + s as i32, y0 + s as i32)],
                    RGBColor(90, 90, 90).stroke_width(1),
                ));
            }
            text(&e.label, x + size * 1.4, y, size, RGBColor(40, 40, 40));
            let w = ("sans-serif", size)
                .into_font()
                .box_size(&e.label)
                .map_or(e.label.len() as f64 * size * 0.55, |(w, _)| f64::from(w));
            x += size * 1.6 + w + pad * 1.5;
        }
    }
    let _ = root.present();
}
