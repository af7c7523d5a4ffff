//! Colours: a categorical palette for ids (a golden-ratio walk around the hue circle), the fixed
//! colours of the pictures, and Lambert shading.

/// Background of the pictures.
pub const BACKGROUND: [u8; 3] = [255, 255, 255];
/// Dark outlines (intermediate-cluster boundaries).
pub const OUTLINE: [u8; 3] = [25, 25, 30];
/// Triangles not involved in a contact.
pub const NEUTRAL: [u8; 3] = [205, 205, 200];
/// Triangles involved in a contact.
pub const CONTACT: [u8; 3] = [220, 25, 20];

/// Triangles involved only in crack contacts: pairs of features joined through a split
/// vertex (a new vertex and its parent), which touch by construction and are not collisions.
pub const CRACK: [u8; 3] = [240, 165, 20];
/// The mesh at the end of the step (t=1), drawn as a ghost outline.
pub const GHOST: [u8; 3] = [40, 100, 210];

/// Share of the light that reaches every surface, whatever its orientation, in `[0, 1]`.
pub const AMBIENT: f64 = 0.35;

/// The golden ratio's fractional part: successive hues are as far apart as possible.
const GOLDEN: f64 = 0.618_033_988_749_895;

/// A distinct colour for category `id`: OKLCH with a constant perceived lightness (so the
/// shading, not the palette, shows the shape) and chroma, and hue `0.1 + id * 0.618...` turns
/// (a golden-ratio walk: any few consecutive ids are far apart on the hue circle).
/// Deterministic.
pub fn categorical(id: u32) -> [u8; 3] {
    let hue = (0.1 + f64::from(id) * GOLDEN).fract();
    oklch(0.80, 0.12, hue)
}

/// OKLCH (lightness in `[0, 1]`, chroma `>= 0`, hue in turns) to 8-bit sRGB, clamping colours
/// outside the gamut.
pub fn oklch(lightness: f64, chroma: f64, hue_turns: f64) -> [u8; 3] {
    let angle = hue_turns * std::f64::consts::TAU;
    let (a, b) = (chroma * angle.cos(), chroma * angle.sin());
    // OKLab to linear sRGB (Björn Ottosson's matrices).
    let l = lightness + 0.396_337_777_4 * a + 0.215_803_757_3 * b;
    let m = lightness - 0.105_561_345_8 * a - 0.063_854_172_8 * b;
    let s = lightness - 0.089_484_177_5 * a - 1.291_485_548_0 * b;
    let (l, m, s) = (l * l * l, m * m * m, s * s * s);
    let rgb = [
        4.076_741_662_1 * l - 3.307_711_591_3 * m + 0.230_969_929_2 * s,
        -1.268_438_004_6 * l + 2.609_757_401_1 * m - 0.341_319_396_5 * s,
        -0.004_196_086_3 * l - 0.703_418_614_7 * m + 1.707_614_701_0 * s,
    ];
    rgb.map(|c| to_byte(srgb_gamma(c)))
}

/// Linear light to the sRGB transfer curve, for `c` in `[0, 1]` (clamped).
fn srgb_gamma(c: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// `color` lit by Lambert's law with ambient light, two-sided: the factor is
/// `AMBIENT + (1 - AMBIENT) |n·l|` for unit normal `n` and unit light direction `l`.
pub fn shade(color: [u8; 3], normal: topoccd::math::DVec3, light: topoccd::math::DVec3) -> [u8; 3] {
    let lambert = normal.dot(light).abs();
    // `f64::min` would turn NaN into 1: test first.
    let lambert = if lambert.is_finite() {
        lambert.min(1.0)
    } else {
        0.0
    };
    let factor = AMBIENT + (1.0 - AMBIENT) * lambert;
    color.map(|c| to_byte(f64::from(c) / 255.0 * factor))
}

/// `a` covered by `b` with opacity `alpha` in `[0, 1]`: `(1 - alpha) a + alpha b`.
pub fn mix(a: [u8; 3], b: [u8; 3], alpha: f64) -> [u8; 3] {
    let alpha = alpha.clamp(0.0, 1.0);
    std::array::from_fn(|k| {
        to_byte(((1.0 - alpha) * f64::from(a[k]) + alpha * f64::from(b[k])) / 255.0)
    })
}

fn to_byte(x: f64) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use topoccd::math::DVec3;

    fn distance(a: [u8; 3], b: [u8; 3]) -> i32 {
        (0..3)
            .map(|k| (i32::from(a[k]) - i32::from(b[k])).abs())
            .sum()
    }

    #[test]
    fn neighbouring_ids_get_clearly_different_colours() {
        for id in 0..2000 {
            let d = distance(categorical(id), categorical(id + 1));
            assert!(d > 60, "ids {id} and {}: {d}", id + 1);
        }
        assert_eq!(categorical(7), categorical(7));
    }

    #[test]
    fn mixing() {
        assert_eq!(mix([0, 100, 255], [255, 200, 55], 0.0), [0, 100, 255]);
        assert_eq!(mix([0, 100, 255], [255, 200, 55], 1.0), [255, 200, 55]);
        assert_eq!(mix([0, 100, 255], [255, 200, 55], 0.5), [128, 150, 155]);
    }

    #[test]
    fn oklch_greys_and_extremes() {
        assert_eq!(oklch(1.0, 0.0, 0.3), [255, 255, 255]);
        assert_eq!(oklch(0.0, 0.0, 0.3), [0, 0, 0]);
        let grey = oklch(0.6, 0.0, 0.0);
        assert!(grey[0] == grey[1] && grey[1] == grey[2]);
        // Out-of-gamut colours are clamped, not wrapped.
        assert_eq!(oklch(0.5, 5.0, 0.0).len(), 3);
    }

    #[test]
    fn shading_is_two_sided_and_never_black() {
        let c = [200, 100, 60];
        assert_eq!(shade(c, DVec3::Z, DVec3::Z), c);
        assert_eq!(shade(c, DVec3::NEG_Z, DVec3::Z), c);
        let side = shade(c, DVec3::X, DVec3::Z);
        assert_eq!(side, c.map(|x| (f64::from(x) * AMBIENT).round() as u8));
        assert_eq!(shade(c, DVec3::ZERO, DVec3::Z), side);
        assert_eq!(shade(c, DVec3::splat(f64::NAN), DVec3::Z), side);
    }
}
