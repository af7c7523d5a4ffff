//! A small headless renderer for `topoccd render`: no display, no GPU, deterministic output.
//!
//! - [`camera`]: an orthographic camera from azimuth and elevation that frames the whole mesh
//!   (orthographic, so depth is linear on screen and nothing needs clipping against a near
//!   plane).
//! - [`raster`]: a z-buffered triangle rasteriser with exact integer edge functions and the
//!   top-left fill rule; outlines are drawn inside the triangles, along marked edges, so they
//!   are hidden exactly where their triangles are.
//! - [`palette`]: categorical colours, Lambert + ambient two-sided flat shading.
//! - [`paint`]: per-triangle colours and outlines by object, cluster or contact.
//! - [`contacts`]: the pairs file and the triangles a list of contacts involves.
//! - [`encode`]: PNG output, true colour or with a palette.
//!
//! [`draw`] renders at a multiple of the requested size and averages each block of samples
//! (supersampling), which smooths edges and outlines.

pub mod camera;
pub mod contacts;
pub mod encode;
pub mod paint;
pub mod palette;
pub mod raster;

use camera::{Camera, View};
use image::RgbImage;
use paint::TriangleStyle;
use raster::{Outline, Raster};
use topoccd::math::DVec3;

/// Most samples (pixels times supersampling factor squared) [`draw`] will allocate; above it
/// the supersampling factor drops, down to 1.
const SAMPLE_BUDGET: u64 = 12 << 20;

/// Largest supersampling factor.
const MAX_SUPERSAMPLING: u32 = 3;

/// Width of an outline inside each of its triangles, in output pixels: an edge between two
/// triangles gets a line twice as wide.
const OUTLINE_HALF_WIDTH: f64 = 0.4;

/// How much of the outline colour covers the triangle's colour, in `[0, 1]`: the leaf colours
/// stay readable through dense outlines.
const OUTLINE_OPACITY: f64 = 0.5;

/// Supersampling factor for a `width x height` picture: the largest factor up to
/// [`MAX_SUPERSAMPLING`] that keeps the samples within [`SAMPLE_BUDGET`] (at least 1).
pub fn supersampling(width: u32, height: u32) -> u32 {
    let pixels = u64::from(width) * u64::from(height);
    (1..=MAX_SUPERSAMPLING)
        .rev()
        .find(|&k| pixels * u64::from(k * k) <= SAMPLE_BUDGET)
        .unwrap_or(1)
}

/// Draws triangles `triangles` over `positions`, triangle `t` styled by `styles[t]`, seen from
/// `view`, as a `width x height` picture on a white background, supersampled `samples` times
/// in each direction (`>= 1`; see [`supersampling`]). The camera frames the vertices the
/// triangles use. Triangles naming a vertex out of range, or of zero area, are skipped.
pub fn draw(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    styles: &[TriangleStyle],
    view: &View,
    width: u32,
    height: u32,
    samples: u32,
) -> RgbImage {
    debug_assert_eq!(triangles.len(), styles.len());
    let k = samples.max(1);
    let (sw, sh) = (width * k, height * k);
    let vertex = |i: u32| positions.get(i as usize).copied();
    let used = triangles.iter().flatten().filter_map(|&i| vertex(i));
    let camera = Camera::framing(used, view, sw, sh);
    let light = camera.light_direction();
    let mut raster = Raster::new(sw, sh, palette::BACKGROUND);
    for (tri, style) in triangles.iter().zip(styles) {
        let (Some(a), Some(b), Some(c)) = (vertex(tri[0]), vertex(tri[1]), vertex(tri[2])) else {
            continue;
        };
        let normal = (b - a).cross(c - a).normalize_or_zero();
        if normal == DVec3::ZERO {
            continue; // zero area in space
        }
        let color = palette::shade(style.color, normal, light);
        let outline = Outline {
            edges: style.outline,
            half_width: OUTLINE_HALF_WIDTH * f64::from(k),
            color: palette::mix(color, palette::OUTLINE, OUTLINE_OPACITY),
        };
        let screen = [camera.project(a), camera.project(b), camera.project(c)];
        let outline = style.outline.contains(&true).then_some(&outline);
        raster.fill_triangle(&screen, color, outline);
    }
    downsample(&raster, k, width, height)
}

/// Averages each `k x k` block of samples into one pixel (rounding to nearest).
fn downsample(raster: &Raster, k: u32, width: u32, height: u32) -> RgbImage {
    let n = k * k;
    let (stride, samples) = (raster.width() as usize, raster.pixels());
    RgbImage::from_fn(width, height, |x, y| {
        let mut sum = [0u32; 3];
        for dy in 0..k {
            let row = (y * k + dy) as usize * stride;
            for p in &samples[row + (x * k) as usize..row + ((x + 1) * k) as usize] {
                for c in 0..3 {
                    sum[c] += u32::from(p[c]);
                }
            }
        }
        image::Rgb(sum.map(|s| ((s + n / 2) / n) as u8))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use paint::TriangleStyle;

    fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = (0..8)
            .map(|i| DVec3::new(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2)))
            .collect();
        let quads = [
            [0, 1, 3, 2],
            [4, 6, 7, 5],
            [0, 4, 5, 1],
            [2, 3, 7, 6],
            [0, 2, 6, 4],
            [1, 5, 7, 3],
        ];
        let tris = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        (p, tris)
    }

    fn non_background(img: &RgbImage) -> usize {
        img.pixels().filter(|p| p.0 != palette::BACKGROUND).count()
    }

    #[test]
    fn a_cube_is_drawn_inside_the_frame_and_deterministically() {
        let (p, t) = cube();
        let styles: Vec<_> = (0..t.len() as u32)
            .map(|i| TriangleStyle::plain(palette::categorical(i)))
            .collect();
        let a = draw(&p, &t, &styles, &View::default(), 64, 48, 2);
        let b = draw(&p, &t, &styles, &View::default(), 64, 48, 2);
        assert_eq!(a, b);
        assert!(non_background(&a) > 400);
        // Nothing touches the border: the whole cube is inside.
        for x in 0..64 {
            assert_eq!(a.get_pixel(x, 0).0, palette::BACKGROUND);
            assert_eq!(a.get_pixel(x, 47).0, palette::BACKGROUND);
        }
        for y in 0..48 {
            assert_eq!(a.get_pixel(0, y).0, palette::BACKGROUND);
            assert_eq!(a.get_pixel(63, y).0, palette::BACKGROUND);
        }
    }

    #[test]
    fn an_edge_on_square_and_degenerate_input_draw_nothing_and_do_not_panic() {
        // A square in the plane z = 0 seen along x (up to rounding in cos 90°): zero area on
        // screen.
        let p = vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let t = vec![[0, 1, 2], [0, 2, 3]];
        let styles = vec![TriangleStyle::plain([1, 2, 3]); 2];
        let side = View {
            azimuth_deg: 90.0,
            elevation_deg: 0.0,
            ..View::default()
        };
        let img = draw(&p, &t, &styles, &side, 32, 32, 1);
        assert_eq!(non_background(&img), 0);
        // Repeated vertices, out-of-range indices, no triangles, a 1x1 picture.
        let bad = vec![[0, 0, 1], [0, 1, 99]];
        assert_eq!(non_background(&draw(&p, &bad, &styles, &side, 8, 8, 1)), 0);
        assert_eq!(non_background(&draw(&p, &[], &[], &side, 8, 8, 1)), 0);
        let one = draw(&p, &t, &styles, &View::default(), 1, 1, 3);
        assert_eq!(one.dimensions(), (1, 1));
    }

    #[test]
    fn supersampling_stays_within_budget() {
        assert_eq!(supersampling(1024, 768), 3);
        assert_eq!(supersampling(1, 1), 3);
        assert_eq!(supersampling(1920, 1080), 2);
        assert_eq!(supersampling(8192, 8192), 1);
    }
}
