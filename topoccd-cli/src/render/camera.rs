//! The orthographic camera: a view direction from azimuth and elevation, framing the mesh's
//! projection so that all of it is inside the picture, as large as fits.

use super::raster::ScreenVertex;
use topoccd::math::DVec3;

/// Which world axis points up in the picture.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum UpAxis {
    /// `+x` up; at azimuth 0, elevation 0 the camera looks along `+z` with `+y` to the right.
    X,
    /// `+y` up (the default); at azimuth 0, elevation 0 the camera looks along `-z` with `+x` to
    /// the right.
    #[default]
    Y,
    /// `+z` up; at azimuth 0, elevation 0 the camera looks along `+y` with `+x` to the right.
    Z,
}

impl UpAxis {
    /// Right, up and towards-the-viewer directions at azimuth 0, elevation 0 (right-handed).
    fn basis(self) -> [DVec3; 3] {
        match self {
            UpAxis::X => [DVec3::Y, DVec3::X, DVec3::NEG_Z],
            UpAxis::Y => [DVec3::X, DVec3::Y, DVec3::Z],
            UpAxis::Z => [DVec3::X, DVec3::Z, DVec3::NEG_Y],
        }
    }
}

/// Where the camera looks from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Rotation of the camera around the up axis, in degrees; positive values move the camera
    /// towards the right of the azimuth-0 view. Any finite value.
    pub azimuth_deg: f64,
    /// Angle of the camera above the horizontal plane, in degrees, `[-90, 90]` (90 looks
    /// straight down).
    pub elevation_deg: f64,
    /// The world axis that points up in the picture.
    pub up: UpAxis,
}

impl Default for View {
    /// A three-quarter view: azimuth 35, elevation 25, `+y` up.
    fn default() -> Self {
        Self {
            azimuth_deg: 35.0,
            elevation_deg: 25.0,
            up: UpAxis::Y,
        }
    }
}

/// Fraction of the picture the whole mesh's projection fills (the rest is margin).
pub const FILL_ALL: f64 = 0.94;

/// An orthographic camera mapping world points to pixels (see [`ScreenVertex`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// World point at depth 0 (the centre of the points' bounding box).
    centre: DVec3,
    right: DVec3,
    up: DVec3,
    toward_viewer: DVec3,
    /// Pixels per world unit.
    scale: f64,
    /// Pixel position of `centre`.
    origin: [f64; 2],
}

impl Camera {
    /// A camera for a `width x height` picture looking from `view` at the given points, with
    /// the scale and the centring chosen so that the rectangle bounding their projections fills
    /// the fraction `fill` (in `(0, 1]`, e.g. [`FILL_ALL`]) of the picture's width or height
    /// (whichever is tighter), centred: every point is inside the picture. Without points, or
    /// when they all project to one point, one world unit spans `fill / 2` of the smaller side.
    /// Non-finite points are ignored.
    pub fn framing(
        points: impl IntoIterator<Item = DVec3> + Clone,
        view: &View,
        width: u32,
        height: u32,
        fill: f64,
    ) -> Self {
        let fill = if fill > 0.0 && fill <= 1.0 {
            fill
        } else {
            FILL_ALL
        };
        let finite = || points.clone().into_iter().filter(|p| p.is_finite());
        let (lo, hi) = finite().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        let centre = if lo.x <= hi.x {
            (lo + hi) * 0.5
        } else {
            DVec3::ZERO
        };

        let (az, el) = (
            view.azimuth_deg.to_radians(),
            view.elevation_deg.clamp(-90.0, 90.0).to_radians(),
        );
        let [r0, u0, t0] = view.up.basis();
        let toward_viewer = (t0 * az.cos() + r0 * az.sin()) * el.cos() + u0 * el.sin();
        let right = r0 * az.cos() - t0 * az.sin();
        let up = toward_viewer.cross(right);

        // Bounding rectangle of the projections, in world units from `centre`.
        let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for p in finite() {
            let d = p - centre;
            let (x, y) = (d.dot(right), d.dot(up));
            (x_lo, x_hi, y_lo, y_hi) = (x_lo.min(x), x_hi.max(x), y_lo.min(y), y_hi.max(y));
        }
        let (w, h) = (f64::from(width), f64::from(height));
        let fit = |pixels: f64, extent: f64| {
            if extent > 0.0 && extent.is_finite() {
                fill * pixels / extent
            } else {
                f64::INFINITY
            }
        };
        let scale = fit(w, x_hi - x_lo).min(fit(h, y_hi - y_lo));
        let scale = if scale.is_finite() {
            scale
        } else {
            0.5 * fill * w.min(h)
        };
        Self {
            centre,
            right,
            up,
            toward_viewer,
            scale,
            origin: [
                0.5 * w - scale * 0.5 * (x_lo + x_hi),
                0.5 * h + scale * 0.5 * (y_lo + y_hi),
            ],
        }
    }

    /// Pixels per world unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// The pixel position and depth of a world point (depth grows away from the viewer, in
    /// world units from the centre of the points' bounding box).
    pub fn project(&self, p: DVec3) -> ScreenVertex {
        let d = p - self.centre;
        ScreenVertex {
            x: self.origin[0] + self.scale * d.dot(self.right),
            y: self.origin[1] - self.scale * d.dot(self.up),
            depth: -d.dot(self.toward_viewer),
        }
    }

    /// Unit direction towards the light: over the viewer's left shoulder.
    pub fn light_direction(&self) -> DVec3 {
        (self.toward_viewer * 0.75 + self.up * 0.55 - self.right * 0.35).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        a.distance(b) < 1e-12
    }

    #[test]
    fn the_basis_is_orthonormal_and_right_handed_from_every_view() {
        for up in [UpAxis::X, UpAxis::Y, UpAxis::Z] {
            for az in [-720.0, -35.0, 0.0, 35.0, 90.0, 181.0] {
                for el in [-90.0, -25.0, 0.0, 25.0, 89.999, 90.0] {
                    let view = View {
                        azimuth_deg: az,
                        elevation_deg: el,
                        up,
                    };
                    let c = Camera::framing([DVec3::ZERO, DVec3::ONE], &view, 10, 10, FILL_ALL);
                    for v in [c.right, c.up, c.toward_viewer] {
                        assert!((v.length() - 1.0).abs() < 1e-12);
                    }
                    assert!(close(c.right.cross(c.up), c.toward_viewer));
                    assert!(c.light_direction().is_finite());
                }
            }
        }
    }

    #[test]
    fn front_views_look_as_documented() {
        let front = |up| View {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            up,
        };
        let c = Camera::framing([DVec3::ZERO], &front(UpAxis::Y), 100, 100, FILL_ALL);
        assert!(close(c.toward_viewer, DVec3::Z) && close(c.right, DVec3::X));
        let c = Camera::framing([DVec3::ZERO], &front(UpAxis::Z), 100, 100, FILL_ALL);
        assert!(close(c.toward_viewer, DVec3::NEG_Y) && close(c.up, DVec3::Z));
        // Looking straight down with y up: the picture's up is -z.
        let top = View {
            elevation_deg: 90.0,
            ..front(UpAxis::Y)
        };
        let c = Camera::framing([DVec3::ZERO], &top, 100, 100, FILL_ALL);
        assert!(close(c.toward_viewer, DVec3::Y) && close(c.up, DVec3::NEG_Z));
    }

    #[test]
    fn framing_puts_every_point_inside_the_picture_from_every_view() {
        // An elongated, off-centre point cloud.
        let points: Vec<DVec3> = (0..200)
            .map(|i| {
                let t = f64::from(i);
                DVec3::new(
                    100.0 + 30.0 * (t * 0.37).sin(),
                    -5.0 + 2.0 * (t * 1.3).cos(),
                    t * 0.01,
                )
            })
            .collect();
        for (w, h) in [(1024, 768), (1, 1), (3, 500), (500, 3)] {
            for az in [0.0, 35.0, 90.0, 200.0] {
                for el in [-90.0, 0.0, 25.0, 90.0] {
                    let view = View {
                        azimuth_deg: az,
                        elevation_deg: el,
                        up: UpAxis::Y,
                    };
                    let c = Camera::framing(points.iter().copied(), &view, w, h, FILL_ALL);
                    let (mut x_lo, mut x_hi) = (f64::INFINITY, f64::NEG_INFINITY);
                    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
                    for p in &points {
                        let s = c.project(*p);
                        assert!(s.x >= 0.0 && s.x <= f64::from(w), "{s:?} in {w}x{h}");
                        assert!(s.y >= 0.0 && s.y <= f64::from(h), "{s:?} in {w}x{h}");
                        (x_lo, x_hi) = (x_lo.min(s.x), x_hi.max(s.x));
                        (y_lo, y_hi) = (y_lo.min(s.y), y_hi.max(s.y));
                    }
                    // As large as fits: one direction filled to 94%, both centred.
                    let (fx, fy) = ((x_hi - x_lo) / f64::from(w), (y_hi - y_lo) / f64::from(h));
                    assert!((fx.max(fy) - 0.94).abs() < 1e-9, "{fx} {fy}");
                    assert!((x_lo + x_hi - f64::from(w)).abs() < 1e-9);
                    assert!((y_lo + y_hi - f64::from(h)).abs() < 1e-9);
                }
            }
        }
    }

    #[test]
    fn the_nearer_point_has_the_smaller_depth() {
        let c = Camera::framing(
            [DVec3::ZERO, DVec3::ONE],
            &View::default(),
            10,
            10,
            FILL_ALL,
        );
        let near = c.project(c.centre + c.toward_viewer);
        let far = c.project(c.centre - c.toward_viewer);
        assert!(near.depth < far.depth);
        assert!((near.x - far.x).abs() < 1e-9 && (near.y - far.y).abs() < 1e-9);
    }

    #[test]
    fn degenerate_point_sets_still_give_a_finite_camera() {
        for points in [
            vec![],
            vec![DVec3::splat(3.0); 4],
            vec![DVec3::splat(f64::NAN)],
        ] {
            let c = Camera::framing(points, &View::default(), 64, 48, FILL_ALL);
            let s = c.project(DVec3::ZERO);
            assert!(s.x.is_finite() && s.y.is_finite() && s.depth.is_finite());
        }
    }
}
