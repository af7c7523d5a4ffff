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

pub mod annotate;
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

/// Fraction of the picture the focused triangles fill (see [`DrawOptions::focus`]): the rest
/// shows what surrounds them.
pub const FILL_FOCUS: f64 = 0.5;

/// How [`draw`] makes a picture.
#[derive(Clone, Copy, Debug)]
pub struct DrawOptions<'a> {
    /// Where the camera looks from.
    pub view: View,
    /// Picture width in pixels, `>= 1` (with `height`, at most [`SAMPLE_BUDGET`] pixels).
    pub width: u32,
    /// Picture height in pixels, `>= 1`.
    pub height: u32,
    /// Supersampling factor in each direction, `1..=3` (see [`supersampling`]).
    pub samples: u32,
    /// Triangles to frame: `None` frames the whole mesh; `Some(marked)` frames the triangles
    /// `t` with `marked[t]` (filling [`FILL_FOCUS`] of the picture, the rest of the mesh
    /// around them and clipped at the picture's edges), unless that would show less than
    /// the whole mesh framed, or none is marked: then the whole mesh is framed.
    pub focus: Option<&'a [bool]>,
    /// Triangles `t` with `marked[t]` show through whatever hides them, faded (with opacity
    /// [`SHOW_THROUGH_OPACITY`]), so that they are seen wherever they are. `None`: none.
    pub show_through: Option<&'a [bool]>,
    /// Another state of the same triangles (the step's end, t=1), drawn as a faint ghost: its
    /// silhouette outlined in [`palette::GHOST`] over the picture, its area tinted where
    /// nothing else is drawn. The camera frames both states. `None`: no ghost.
    pub ghost: Option<&'a [DVec3]>,
}

/// Opacity of the ghost's tint where nothing else is drawn (see [`DrawOptions::ghost`]).
pub const GHOST_FILL: f64 = 0.18;
/// Opacity of the ghost's silhouette line.
pub const GHOST_LINE: f64 = 0.85;

/// Opacity of the triangles that show through nearer surfaces (see
/// [`DrawOptions::show_through`]).
pub const SHOW_THROUGH_OPACITY: f64 = 0.55;

/// Draws triangles `triangles` over `positions`, triangle `t` styled by `styles[t]`, as a
/// picture on a white background (see [`DrawOptions`]). Triangles naming a vertex out of
/// range, or of zero area, are skipped.
pub fn draw(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    styles: &[TriangleStyle],
    options: &DrawOptions,
) -> RgbImage {
    debug_assert_eq!(triangles.len(), styles.len());
    let (width, height) = (options.width, options.height);
    let k = options.samples.clamp(1, MAX_SUPERSAMPLING);
    let (sw, sh) = (width * k, height * k);
    let vertex = |i: u32| positions.get(i as usize).copied();
    let used = |keep: &dyn Fn(usize) -> bool| {
        let points = triangles
            .iter()
            .enumerate()
            .filter(move |&(t, _)| keep(t))
            .flat_map(move |(_, tri)| tri.iter().filter_map(move |&i| vertex(i)));
        points.collect::<Vec<DVec3>>()
    };
    let mut all = used(&|_| true);
    if let Some(ghost) = options.ghost {
        let vertex = |i: u32| ghost.get(i as usize).copied();
        all.extend(
            triangles
                .iter()
                .flat_map(|tri| tri.iter().filter_map(|&i| vertex(i))),
        );
    }
    let whole = Camera::framing(all.iter().copied(), &options.view, sw, sh, camera::FILL_ALL);
    // Framing the focused triangles only ever zooms in.
    let camera = match options.focus.filter(|f| f.contains(&true)) {
        Some(marked) => {
            let points = used(&|t| marked.get(t) == Some(&true));
            let focused =
                Camera::framing(points.iter().copied(), &options.view, sw, sh, FILL_FOCUS);
            if focused.scale() > whole.scale() {
                focused
            } else {
                whole
            }
        }
        None => whole,
    };
    let painter = Painter {
        camera,
        light: camera.light_direction(),
        outline_half_width: OUTLINE_HALF_WIDTH * f64::from(k),
        positions,
        triangles,
        styles,
    };
    let mut raster = Raster::new(sw, sh, palette::BACKGROUND);
    painter.draw(&mut raster, &|_| true);
    if let Some(marked) = options.show_through.filter(|m| m.contains(&true)) {
        let mut hidden = Raster::new(sw, sh, palette::BACKGROUND);
        painter.draw(&mut hidden, &|t| marked.get(t) == Some(&true));
        raster.show_through(&hidden, SHOW_THROUGH_OPACITY);
    }
    if let Some(ghost) = options.ghost {
        let ghost_styles = vec![TriangleStyle::plain(palette::GHOST); triangles.len()];
        let ghost_painter = Painter {
            positions: ghost,
            styles: &ghost_styles,
            ..painter
        };
        let mut shadow = Raster::new(sw, sh, palette::BACKGROUND);
        ghost_painter.draw(&mut shadow, &|_| true);
        raster.ghost_over(&shadow, palette::GHOST, GHOST_FILL, GHOST_LINE, k);
    }
    downsample(&raster, k, width, height)
}

/// The mesh, its styles and the camera: what every pass of [`draw`] needs.
struct Painter<'a> {
    camera: Camera,
    light: DVec3,
    outline_half_width: f64,
    positions: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    styles: &'a [TriangleStyle],
}

impl Painter<'_> {
    /// Draws the triangles `t` with `keep(t)`, shaded and outlined, into `raster`.
    fn draw(&self, raster: &mut Raster, keep: &dyn Fn(usize) -> bool) {
        let vertex = |i: u32| self.positions.get(i as usize).copied();
        for (t, (tri, style)) in self.triangles.iter().zip(self.styles).enumerate() {
            if !keep(t) {
                continue;
            }
            let (Some(a), Some(b), Some(c)) = (vertex(tri[0]), vertex(tri[1]), vertex(tri[2]))
            else {
                continue;
            };
            let normal = (b - a).cross(c - a).normalize_or_zero();
            if normal == DVec3::ZERO {
                continue; // zero area in space
            }
            let color = palette::shade(style.color, normal, self.light);
            let outline = Outline {
                edges: style.outline,
                half_width: self.outline_half_width,
                color: palette::mix(color, palette::OUTLINE, OUTLINE_OPACITY),
            };
            let screen = [a, b, c].map(|p| self.camera.project(p));
            let outline = style.outline.contains(&true).then_some(&outline);
            raster.fill_triangle(&screen, color, outline);
        }
    }
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
        let options = DrawOptions {
            view: View::default(),
            width: 64,
            height: 48,
            samples: 2,
            focus: None,
            show_through: None,
            ghost: None,
        };
        let a = draw(&p, &t, &styles, &options);
        let b = draw(&p, &t, &styles, &options);
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
        let options = |view, size, samples| DrawOptions {
            view,
            width: size,
            height: size,
            samples,
            focus: None,
            show_through: None,
            ghost: None,
        };
        let img = draw(&p, &t, &styles, &options(side, 32, 1));
        assert_eq!(non_background(&img), 0);
        // Repeated vertices, out-of-range indices, no triangles, a 1x1 picture.
        let bad = vec![[0, 0, 1], [0, 1, 99]];
        assert_eq!(
            non_background(&draw(&p, &bad, &styles, &options(side, 8, 1))),
            0
        );
        assert_eq!(non_background(&draw(&p, &[], &[], &options(side, 8, 1))), 0);
        let one = draw(&p, &t, &styles, &options(View::default(), 1, 3));
        assert_eq!(one.dimensions(), (1, 1));
    }

    #[test]
    fn focus_frames_the_marked_triangles_with_the_rest_around_them() {
        // A unit triangle beside a big one, in the plane z = 0, seen from the front.
        let p = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(1.2, -5.0, 0.0),
            DVec3::new(20.0, -5.0, 0.0),
            DVec3::new(1.2, 20.0, 0.0),
        ];
        let t = vec![[0, 1, 2], [3, 4, 5]];
        let styles = vec![
            TriangleStyle::plain([200, 0, 0]),
            TriangleStyle::plain([0, 0, 200]),
        ];
        let front = View {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            ..View::default()
        };
        let marked = [true, false];
        let options = DrawOptions {
            view: front,
            width: 100,
            height: 100,
            samples: 1,
            focus: Some(&marked),
            show_through: None,
            ghost: None,
        };
        let img = draw(&p, &t, &styles, &options);
        let own = count_color(&img, shaded(&styles[0], &p, t[0], &front));
        // The unit triangle fills half the picture's side (half of a 50x50 square), and the
        // big one shows beside it, clipped.
        assert!((1150..=1350).contains(&own), "{own}");
        assert!(non_background(&img) > own + 1000);
        // Nothing marked, or only the big triangle: the whole mesh is framed, as without focus.
        let unfocused = DrawOptions {
            focus: None,
            ..options
        };
        let all = draw(&p, &t, &styles, &unfocused);
        for marked in [[false, false], [false, true]] {
            let options = DrawOptions {
                focus: Some(&marked),
                ..options
            };
            assert_eq!(draw(&p, &t, &styles, &options), all);
        }
    }

    fn count_color(img: &RgbImage, c: [u8; 3]) -> usize {
        img.pixels().filter(|p| p.0 == c).count()
    }

    fn shaded(style: &TriangleStyle, p: &[DVec3], [a, b, c]: [u32; 3], view: &View) -> [u8; 3] {
        let [a, b, c] = [a, b, c].map(|i| p[i as usize]);
        let camera = Camera::framing(p.iter().copied(), view, 1, 1, camera::FILL_ALL);
        let normal = (b - a).cross(c - a).normalize();
        palette::shade(style.color, normal, camera.light_direction())
    }

    #[test]
    fn supersampling_stays_within_budget() {
        assert_eq!(supersampling(1024, 768), 3);
        assert_eq!(supersampling(1, 1), 3);
        assert_eq!(supersampling(1920, 1080), 2);
        assert_eq!(supersampling(8192, 8192), 1);
    }
}
