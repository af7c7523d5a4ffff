//! Second-order forward differentiation over `N` variables: a value with its gradient and its
//! (symmetric, dense) Hessian. The distances of a contact stencil (up to 12 coordinates) are
//! written once as plain arithmetic on these numbers, and their exact first and second
//! derivatives follow by the chain rule, to rounding.

use std::ops::{Add, Mul, Neg, Sub};

/// A scalar function of `N` variables at a point: value, gradient, Hessian.
#[derive(Clone, Copy, Debug)]
pub struct Hd<const N: usize> {
    pub v: f64,
    pub g: [f64; N],
    pub h: [[f64; N]; N],
}

impl<const N: usize> Hd<N> {
    pub fn constant(v: f64) -> Self {
        Self {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }

    /// The variable `i` with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut x = Self::constant(v);
        x.g[i] = 1.0;
        x
    }

    /// `f(self)` from `f`, `f'` and `f''` at `self.v`.
    pub fn chain(&self, f: f64, df: f64, d2f: f64) -> Self {
        let mut out = Self::constant(f);
        for i in 0..N {
            out.g[i] = df * self.g[i];
        }
        for i in 0..N {
            for j in 0..N {
                out.h[i][j] = df * self.h[i][j] + d2f * self.g[i] * self.g[j];
            }
        }
        out
    }

    pub fn scale(&self, s: f64) -> Self {
        self.chain(s * self.v, s, 0.0)
    }

    pub fn recip(&self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }

    pub fn div(&self, other: &Self) -> Self {
        *self * other.recip()
    }
}

impl<const N: usize> Add for Hd<N> {
    type Output = Self;
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
            for j in 0..N {
                self.h[i][j] += o.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize> Sub for Hd<N> {
    type Output = Self;
    fn sub(mut self, o: Self) -> Self {
        self.v -= o.v;
        for i in 0..N {
            self.g[i] -= o.g[i];
            for j in 0..N {
                self.h[i][j] -= o.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize> Neg for Hd<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}

impl<const N: usize> Mul for Hd<N> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut out = Self::constant(self.v * o.v);
        for i in 0..N {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
        }
        for i in 0..N {
            for j in 0..N {
                out.h[i][j] = self.v * o.h[i][j]
                    + o.v * self.h[i][j]
                    + self.g[i] * o.g[j]
                    + o.g[i] * self.g[j];
            }
        }
        out
    }
}

/// A point of three such numbers.
pub type V3<const N: usize> = [Hd<N>; 3];

/// The stencil's coordinates as variables: point `k` is variables `3k..3k+3`.
pub fn points<const N: usize>(x: &[f64]) -> Vec<V3<N>> {
    (0..N / 3)
        .map(|k| [0, 1, 2].map(|c| Hd::var(x[3 * k + c], 3 * k + c)))
        .collect()
}

pub fn sub<const N: usize>(a: &V3<N>, b: &V3<N>) -> V3<N> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn dot<const N: usize>(a: &V3<N>, b: &V3<N>) -> Hd<N> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross<const N: usize>(a: &V3<N>, b: &V3<N>) -> V3<N> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_and_quotient_rules() {
        // f(x, y) = x y / (x + y) at (2, 3): exact derivatives by hand.
        let x = Hd::<2>::var(2.0, 0);
        let y = Hd::<2>::var(3.0, 1);
        let f = (x * y).div(&(x + y));
        assert!((f.v - 1.2).abs() < 1e-15);
        // df/dx = y^2/(x+y)^2 = 9/25, d2f/dx2 = -2 y^2/(x+y)^3 = -18/125, d2f/dxdy = 2xy/(x+y)^3.
        assert!((f.g[0] - 9.0 / 25.0).abs() < 1e-15);
        assert!((f.h[0][0] + 18.0 / 125.0).abs() < 1e-15);
        assert!((f.h[0][1] - 12.0 / 125.0).abs() < 1e-15);
    }
}
