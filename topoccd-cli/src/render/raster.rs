//! A z-buffered triangle rasteriser.
//!
//! Vertices are snapped to a grid of 1/256 pixel and the edge functions are evaluated exactly
//! in integers at pixel centres `(i + 0.5, j + 0.5)`, with the top-left fill rule: a pixel centre
//! exactly on an edge belongs to the triangle only if that edge is a top or a left edge. Two
//! triangles sharing an edge (and lying on opposite sides of it on screen) therefore cover every
//! pixel along it exactly once: no cracks, no double blending. Depth is interpolated linearly in
//! screen space, which is exact for the orthographic camera of [`super::camera`].

/// Bits of sub-pixel precision of the snapped vertex coordinates.
pub const SUBPIXEL_BITS: u32 = 8;

/// Sub-pixel units per pixel.
const SUB: i64 = 1 << SUBPIXEL_BITS;

/// Largest absolute screen coordinate, in pixels, of a vertex that is drawn. A triangle with a
/// vertex farther out (or a non-finite one) is skipped. With coordinates below `2^20` pixels,
/// every edge function fits in an `i64` exactly (`|w| < 2^59`).
pub const MAX_COORDINATE: f64 = (1u64 << 20) as f64;

/// A projected vertex: pixel coordinates (`x` to the right, `y` down, the image spans
/// `[0, width] x [0, height]`) and a depth (smaller is nearer; any finite value).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScreenVertex {
    /// Horizontal position, in pixels.
    pub x: f64,
    /// Vertical position, in pixels, downwards.
    pub y: f64,
    /// Depth along the viewing direction; smaller is nearer.
    pub depth: f64,
}

/// Lines drawn inside a triangle along some of its edges (a triangle draws the half of the line
/// on its side; a neighbour across the edge draws the other half).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outline {
    /// Which edges to draw: edge `k` joins vertex `k` to vertex `(k + 1) % 3`.
    pub edges: [bool; 3],
    /// Width of the half-line drawn inside the triangle, in pixels, `>= 0`.
    pub half_width: f64,
    /// Colour of the line.
    pub color: [u8; 3],
}

/// An RGB image with a depth buffer.
#[derive(Clone, Debug)]
pub struct Raster {
    width: u32,
    height: u32,
    color: Vec<[u8; 3]>,
    depth: Vec<f64>,
}

/// Snapped vertex: sub-pixel coordinates and depth.
#[derive(Clone, Copy, Debug)]
struct Snapped {
    x: i64,
    y: i64,
    depth: f64,
}

/// Twice the signed area of `(a, b, p)`; positive when `p` is on the interior side of `a -> b`
/// for a triangle of positive area (clockwise on screen, as `y` points down).
#[inline]
fn orient(a: Snapped, b: Snapped, px: i64, py: i64) -> i64 {
    (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)
}

/// Whether the edge `a -> b` of a positively oriented triangle is a top edge (horizontal, the
/// interior below it) or a left edge (the interior to its right).
#[inline]
fn is_top_left(a: Snapped, b: Snapped) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    dy < 0 || (dy == 0 && dx > 0)
}

impl Raster {
    /// A `width x height` image filled with `background`, every depth at infinity.
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Self {
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            color: vec![background; n],
            depth: vec![f64::INFINITY; n],
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Colour of pixel `(x, y)`; `x < width`, `y < height`.
    #[cfg(test)]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        self.color[y as usize * self.width as usize + x as usize]
    }

    /// Depth of the nearest triangle at pixel `(x, y)`, or infinity if none covers it.
    #[cfg(test)]
    pub fn depth(&self, x: u32, y: u32) -> f64 {
        self.depth[y as usize * self.width as usize + x as usize]
    }

    /// The pixels row by row, top row first.
    pub fn pixels(&self) -> &[[u8; 3]] {
        &self.color
    }

    /// Shows what `hidden` drew (a raster of the same size, drawn over the same depths) where
    /// this raster has something nearer: its colour is laid over this raster's with opacity
    /// `opacity` in `[0, 1]`, so hidden triangles show through as if the nearer surfaces were
    /// partly transparent. Pixels where `hidden` is the nearest (or drew nothing) are kept.
    pub fn show_through(&mut self, hidden: &Raster, opacity: f64) {
        debug_assert_eq!((self.width, self.height), (hidden.width, hidden.height));
        let alpha = opacity.clamp(0.0, 1.0);
        for (i, (&depth, &color)) in hidden.depth.iter().zip(&hidden.color).enumerate() {
            if depth.is_finite() && self.depth.get(i).is_some_and(|&d| d < depth) {
                let under = self.color[i];
                self.color[i] = std::array::from_fn(|k| {
                    let c = (1.0 - alpha) * f64::from(under[k]) + alpha * f64::from(color[k]);
                    c.round().clamp(0.0, 255.0) as u8
                });
            }
        }
    }

    /// Lays `ghost` (a raster of the same size: another state of the mesh, e.g. its end of
    /// step) over this one: where only the ghost covers a pixel it is tinted with `color` at
    /// opacity `fill` in `[0, 1]`; the ghost's silhouette (covered pixels within `radius`
    /// pixels, along a row or a column, of an uncovered one) is drawn in `color` at opacity
    /// `line` over everything. Deterministic.
    pub fn ghost_over(
        &mut self,
        ghost: &Raster,
        color: [u8; 3],
        fill: f64,
        line: f64,
        radius: u32,
    ) {
        debug_assert_eq!((self.width, self.height), (ghost.width, ghost.height));
        let (w, h) = (self.width as usize, self.height as usize);
        let covered = |x: usize, y: usize| ghost.depth[y * w + x].is_finite();
        let r = radius as usize;
        let blend = |under: [u8; 3], alpha: f64| -> [u8; 3] {
            std::array::from_fn(|k| {
                let c = (1.0 - alpha) * f64::from(under[k]) + alpha * f64::from(color[k]);
                c.round().clamp(0.0, 255.0) as u8
            })
        };
        for y in 0..h {
            for x in 0..w {
                if !covered(x, y) {
                    continue;
                }
                let i = y * w + x;
                let edge = (1..=r).any(|d| {
                    x < d
                        || y < d
                        || x + d >= w
                        || y + d >= h
                        || !covered(x - d, y)
                        || !covered(x + d, y)
                        || !covered(x, y - d)
                        || !covered(x, y + d)
                });
                if edge {
                    self.color[i] = blend(self.color[i], line);
                } else if !self.depth[i].is_finite() {
                    self.color[i] = blend(self.color[i], fill);
                }
            }
        }
    }

    /// Draws a triangle in `color` (and `outline` along its marked edges) where it is nearer
    /// than what is already drawn; on equal depth the earlier triangle stays. Either
    /// orientation is drawn. Triangles of zero area after snapping, and triangles with a
    /// non-finite coordinate or one beyond [`MAX_COORDINATE`], are skipped. Returns the number
    /// of pixels written.
    pub fn fill_triangle(
        &mut self,
        vertices: &[ScreenVertex; 3],
        color: [u8; 3],
        outline: Option<&Outline>,
    ) -> usize {
        let ok = |v: &ScreenVertex| {
            v.x.abs() <= MAX_COORDINATE && v.y.abs() <= MAX_COORDINATE && v.depth.is_finite()
        };
        if !vertices.iter().all(ok) {
            return 0; // also catches NaN: comparisons with NaN are false
        }
        let snap = |v: &ScreenVertex| Snapped {
            x: (v.x * SUB as f64).round() as i64,
            y: (v.y * SUB as f64).round() as i64,
            depth: v.depth,
        };
        let mut q = [snap(&vertices[0]), snap(&vertices[1]), snap(&vertices[2])];
        let mut marked = outline.map_or([false; 3], |o| o.edges);
        let mut area = orient(q[0], q[1], q[2].x, q[2].y);
        if area == 0 {
            return 0;
        }
        if area < 0 {
            // Reverse to (0, 2, 1): its edges are the old edges 2, 1, 0.
            q.swap(1, 2);
            marked = [marked[2], marked[1], marked[0]];
            area = -area;
        }
        let area = area as f64;
        // Edge k joins q[k] to q[k+1]; its function weighs the opposite vertex q[k+2].
        let edge = |k: usize| (q[k], q[(k + 1) % 3]);
        let bias: [i64; 3] = std::array::from_fn(|k| {
            let (a, b) = edge(k);
            i64::from(!is_top_left(a, b))
        });
        // Inverse lengths (in pixels) turn an edge function into a distance in pixels.
        let inv_len: [f64; 3] = std::array::from_fn(|k| {
            let (a, b) = edge(k);
            let len = ((b.x - a.x) as f64).hypot((b.y - a.y) as f64);
            1.0 / (len * SUB as f64)
        });
        let half_width = outline.map_or(0.0, |o| o.half_width);
        let line_color = outline.map_or(color, |o| o.color);

        // Pixel range whose centres `(i * SUB + SUB / 2)` can fall inside.
        let lo = |m: i64| (m - SUB / 2 + SUB - 1).div_euclid(SUB);
        let hi = |m: i64| (m - SUB / 2).div_euclid(SUB);
        let (min_x, max_x) = (q.iter().map(|v| v.x).min(), q.iter().map(|v| v.x).max());
        let (min_y, max_y) = (q.iter().map(|v| v.y).min(), q.iter().map(|v| v.y).max());
        let (Some(min_x), Some(max_x), Some(min_y), Some(max_y)) = (min_x, max_x, min_y, max_y)
        else {
            return 0;
        };
        let x0 = lo(min_x).max(0);
        let x1 = hi(max_x).min(i64::from(self.width) - 1);
        let y0 = lo(min_y).max(0);
        let y1 = hi(max_y).min(i64::from(self.height) - 1);

        let mut written = 0;
        for py in y0..=y1 {
            let cy = py * SUB + SUB / 2;
            let row = py as usize * self.width as usize;
            for px in x0..=x1 {
                let cx = px * SUB + SUB / 2;
                let w: [i64; 3] = std::array::from_fn(|k| {
                    let (a, b) = edge(k);
                    orient(a, b, cx, cy)
                });
                if (0..3).any(|k| w[k] < bias[k]) {
                    continue;
                }
                let depth = (w[1] as f64 * q[0].depth
                    + w[2] as f64 * q[1].depth
                    + w[0] as f64 * q[2].depth)
                    / area;
                let i = row + px as usize;
                if depth < self.depth[i] {
                    self.depth[i] = depth;
                    let on_line =
                        (0..3).any(|k| marked[k] && (w[k] as f64) * inv_len[k] < half_width);
                    self.color[i] = if on_line { line_color } else { color };
                    written += 1;
                }
            }
        }
        written
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const BG: [u8; 3] = [255, 255, 255];
    const RED: [u8; 3] = [255, 0, 0];
    const BLUE: [u8; 3] = [0, 0, 255];

    fn v(x: f64, y: f64, depth: f64) -> ScreenVertex {
        ScreenVertex { x, y, depth }
    }

    fn count(r: &Raster, c: [u8; 3]) -> usize {
        r.pixels().iter().filter(|&&p| p == c).count()
    }

    #[test]
    fn right_triangle_covers_the_pixel_centres_inside_it() {
        let mut r = Raster::new(8, 8, BG);
        // Legs along the top and left of the image: centre (i+.5, j+.5) is inside when
        // i + j + 1 <= 4 (on the hypotenuse only if top-left, which it is not).
        let n = r.fill_triangle(
            &[v(0.0, 0.0, 0.0), v(4.0, 0.0, 0.0), v(0.0, 4.0, 0.0)],
            RED,
            None,
        );
        let mut expected = 0;
        for y in 0..8 {
            for x in 0..8 {
                let inside = x + y + 1 < 4; // centres on the hypotenuse (x + y + 1 == 4) excluded
                expected += usize::from(inside);
                assert_eq!(r.pixel(x, y) == RED, inside, "pixel ({x}, {y})");
            }
        }
        assert_eq!(n, expected);
        assert_eq!(n, 6);
    }

    #[test]
    fn orientation_does_not_matter() {
        let tri = [v(0.3, 0.7, 0.0), v(6.2, 1.1, 0.0), v(2.9, 7.4, 0.0)];
        let mut a = Raster::new(8, 8, BG);
        let mut b = Raster::new(8, 8, BG);
        a.fill_triangle(&tri, RED, None);
        b.fill_triangle(&[tri[0], tri[2], tri[1]], RED, None);
        assert_eq!(a.pixels(), b.pixels());
        assert!(count(&a, RED) > 10);
    }

    #[test]
    fn a_fan_covers_each_pixel_exactly_once() {
        // Triangles around an off-grid centre, their corners also off the grid, tiling a
        // polygon; every pixel covered once: the top-left rule leaves no crack, no overlap.
        let (w, h) = (40u32, 30u32);
        let centre = v(19.37, 14.81, 0.0);
        let ring: Vec<ScreenVertex> = (0..17)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 17.0;
                v(19.37 + 40.0 * a.cos(), 14.81 + 35.0 * a.sin(), 0.0)
            })
            .collect();
        let mut hits = vec![0u32; (w * h) as usize];
        for k in 0..ring.len() {
            // Each triangle on a fresh raster, so the depth test does not hide overlaps.
            let mut r = Raster::new(w, h, BG);
            let tri = [centre, ring[k], ring[(k + 1) % ring.len()]];
            let tri = if k % 2 == 0 {
                tri
            } else {
                [tri[0], tri[2], tri[1]]
            };
            r.fill_triangle(&tri, RED, None);
            for (i, p) in r.pixels().iter().enumerate() {
                hits[i] += u32::from(*p == RED);
            }
        }
        assert!(hits.iter().all(|&n| n == 1), "{hits:?}");
    }

    #[test]
    fn nearer_triangle_occludes_farther_whatever_the_order() {
        let big = [v(0.0, 0.0, 5.0), v(10.0, 0.0, 5.0), v(0.0, 10.0, 5.0)];
        let small = [v(1.0, 1.0, 1.0), v(4.0, 1.0, 1.0), v(1.0, 4.0, 1.0)];
        for near_first in [false, true] {
            let mut r = Raster::new(10, 10, BG);
            if near_first {
                r.fill_triangle(&small, RED, None);
                r.fill_triangle(&big, BLUE, None);
            } else {
                r.fill_triangle(&big, BLUE, None);
                r.fill_triangle(&small, RED, None);
            }
            assert_eq!(r.pixel(1, 1), RED);
            assert_eq!(r.depth(1, 1), 1.0);
            assert_eq!(r.pixel(6, 1), BLUE);
            assert_eq!(r.pixel(9, 9), BG);
        }
    }

    #[test]
    fn hidden_triangles_show_through_nearer_ones() {
        let big = [v(0.0, 0.0, 1.0), v(10.0, 0.0, 1.0), v(0.0, 10.0, 1.0)];
        let hidden = [v(1.0, 1.0, 5.0), v(4.0, 1.0, 5.0), v(1.0, 4.0, 5.0)];
        let in_front = [v(6.0, 6.0, 0.0), v(9.0, 6.0, 0.0), v(6.0, 9.0, 0.0)];
        let mut scene = Raster::new(10, 10, BG);
        for tri in [&big, &hidden, &in_front] {
            scene.fill_triangle(tri, BLUE, None);
        }
        let mut marked = Raster::new(10, 10, BG);
        marked.fill_triangle(&hidden, RED, None);
        marked.fill_triangle(&in_front, RED, None);
        scene.show_through(&marked, 0.5);
        assert_eq!(scene.pixel(1, 1), [128, 0, 128]); // behind `big`: half red, half blue
        assert_eq!(scene.pixel(6, 1), BLUE); // `big` alone
        assert_eq!(scene.pixel(6, 6), BLUE); // nearest already, kept as drawn
        assert_eq!(scene.pixel(9, 0), BG);
    }

    #[test]
    fn depth_is_interpolated_across_the_triangle() {
        let mut r = Raster::new(10, 10, BG);
        // Depth equal to x.
        r.fill_triangle(
            &[v(0.0, 0.0, 0.0), v(10.0, 0.0, 10.0), v(0.0, 10.0, 0.0)],
            RED,
            None,
        );
        assert!((r.depth(2, 3) - 2.5).abs() < 1e-12);
        // A plane with depth 10 - x crosses it at x = 5.
        r.fill_triangle(
            &[v(0.0, 0.0, 10.0), v(10.0, 0.0, 0.0), v(0.0, 10.0, 10.0)],
            BLUE,
            None,
        );
        assert_eq!(r.pixel(3, 1), RED);
        assert_eq!(r.pixel(6, 1), BLUE);
    }

    #[test]
    fn degenerate_and_invalid_triangles_are_skipped() {
        let mut r = Raster::new(10, 10, BG);
        let flat = [v(1.0, 1.0, 0.0), v(5.0, 5.0, 0.0), v(9.0, 9.0, 0.0)];
        assert_eq!(r.fill_triangle(&flat, RED, None), 0);
        let point = [v(3.0, 3.0, 0.0); 3];
        assert_eq!(r.fill_triangle(&point, RED, None), 0);
        let nan = [v(f64::NAN, 0.0, 0.0), v(9.0, 0.0, 0.0), v(0.0, 9.0, 0.0)];
        assert_eq!(r.fill_triangle(&nan, RED, None), 0);
        let nan_depth = [v(0.0, 0.0, f64::NAN), v(9.0, 0.0, 0.0), v(0.0, 9.0, 0.0)];
        assert_eq!(r.fill_triangle(&nan_depth, RED, None), 0);
        let huge = [v(-1e300, 0.0, 0.0), v(9.0, 0.0, 0.0), v(0.0, 9.0, 0.0)];
        assert_eq!(r.fill_triangle(&huge, RED, None), 0);
        assert_eq!(count(&r, BG), 100);
    }

    #[test]
    fn off_screen_parts_are_clipped() {
        let mut r = Raster::new(4, 3, BG);
        let n = r.fill_triangle(
            &[
                v(-100.0, -100.0, 0.0),
                v(100.0, -100.0, 0.0),
                v(0.0, 100.0, 0.0),
            ],
            RED,
            None,
        );
        assert_eq!(n, 12);
        assert_eq!(count(&r, RED), 12);
    }

    #[test]
    fn one_pixel_image() {
        let mut r = Raster::new(1, 1, BG);
        assert_eq!(
            r.fill_triangle(
                &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)],
                RED,
                None
            ),
            0
        );
        assert_eq!(
            r.fill_triangle(
                &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0)],
                RED,
                None
            ),
            1
        );
        assert_eq!(r.pixel(0, 0), RED);
        let mut empty = Raster::new(0, 0, BG);
        assert_eq!(
            empty.fill_triangle(
                &[v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(1.0, 1.0, 0.0)],
                RED,
                None
            ),
            0
        );
    }

    #[test]
    fn outlines_follow_the_marked_edges_only() {
        let mut r = Raster::new(20, 20, BG);
        let outline = Outline {
            edges: [true, false, false], // edge 0: from (0, 0) to (20, 0), the top
            half_width: 2.0,
            color: BLUE,
        };
        r.fill_triangle(
            &[v(0.0, 0.0, 0.0), v(20.0, 0.0, 0.0), v(0.0, 20.0, 0.0)],
            RED,
            Some(&outline),
        );
        assert_eq!(r.pixel(5, 0), BLUE);
        assert_eq!(r.pixel(5, 1), BLUE);
        assert_eq!(r.pixel(5, 2), RED);
        assert_eq!(r.pixel(0, 10), RED); // the left edge is not marked
                                         // The same with the triangle given in the other orientation.
        let mut s = Raster::new(20, 20, BG);
        let flipped = Outline {
            edges: [false, false, true], // edge 2 of (a, c, b) is b -> a: the top again
            ..outline
        };
        s.fill_triangle(
            &[v(0.0, 0.0, 0.0), v(0.0, 20.0, 0.0), v(20.0, 0.0, 0.0)],
            RED,
            Some(&flipped),
        );
        assert_eq!(r.pixels(), s.pixels());
    }
}
