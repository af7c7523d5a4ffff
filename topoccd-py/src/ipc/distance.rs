//! Closest-feature types with ipctk 1.6.1's rules and tie-breaks, and the squared distances
//! by type (friction's normal forces at the lagged positions).
//!
//! Types: point-edge 0 `P_E0`, 1 `P_E1`, 2 `P_E`; point-triangle 0-2 `P_T0..P_T2`, 3-5
//! `P_E0..P_E2` (edge k from corner k to k+1), 6 `P_T`; edge-edge 0 `EA0_EB0`, 1 `EA0_EB1`,
//! 2 `EA1_EB0`, 3 `EA1_EB1`, 4 `EA_EB0`, 5 `EA_EB1`, 6 `EA0_EB`, 7 `EA1_EB`, 8 `EA_EB`.

type P = [f64; 3];

fn s(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn d(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn c(a: P, b: P) -> P {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Which feature of the segment `e0 e1` is closest to `p`.
pub fn point_edge_type(p: P, e0: P, e1: P) -> u8 {
    let e = s(e1, e0);
    let len2 = d(e, e);
    if len2 == 0.0 {
        return 0;
    }
    let r = d(e, s(p, e0)) / len2;
    if r < 0.0 {
        0
    } else if r > 1.0 {
        1
    } else {
        2
    }
}

/// Which feature of the triangle is closest to `p`: for each edge k, the point's coordinates
/// along it and along the outward in-plane normal decide the edge regions, then the corners.
pub fn point_triangle_type(p: P, t0: P, t1: P, t2: P) -> u8 {
    let t = [t0, t1, t2];
    let n = c(s(t1, t0), s(t2, t0));
    let mut along = [0.0; 3];
    for k in 0..3 {
        let b0 = s(t[(k + 1) % 3], t[k]);
        let b1 = c(b0, n);
        let r = s(p, t[k]);
        // The 2x2 normal equations [b0.b0 b0.b1; b0.b1 b1.b1] x = [b0.r; b1.r].
        let (a00, a01, a11) = (d(b0, b0), d(b0, b1), d(b1, b1));
        let (r0, r1) = (d(b0, r), d(b1, r));
        // LDL^T of the symmetric 2x2.
        let l = a01 / a00;
        let d1 = a11 - l * a01;
        let y1 = r1 - l * r0;
        let x1 = y1 / d1;
        let x0 = r0 / a00 - l * x1;
        along[k] = x0;
        if x0 > 0.0 && x0 < 1.0 && x1 >= 0.0 {
            return 3 + k as u8;
        }
    }
    if along[0] <= 0.0 && along[2] >= 1.0 {
        0
    } else if along[1] <= 0.0 && along[0] >= 1.0 {
        1
    } else if along[2] <= 0.0 && along[1] >= 1.0 {
        2
    } else {
        6
    }
}

fn parallel_edge_edge_type(ea0: P, ea1: P, eb0: P, eb1: P) -> u8 {
    let ea = s(ea1, ea0);
    let alpha = d(s(eb0, ea0), ea) / d(ea, ea);
    let beta = d(s(eb1, ea0), ea) / d(ea, ea);
    let (eac, ebc) = if alpha < 0.0 {
        (
            if (0.0..=1.0).contains(&beta) { 2 } else { 0 },
            if beta <= alpha {
                0
            } else if beta <= 1.0 {
                1
            } else {
                2
            },
        )
    } else if alpha > 1.0 {
        (
            if (0.0..=1.0).contains(&beta) { 2 } else { 1 },
            if beta >= alpha {
                0
            } else if 0.0 <= beta {
                1
            } else {
                2
            },
        )
    } else {
        (2, 0)
    };
    if ebc < 2 {
        (eac << 1) | ebc
    } else {
        6 + eac
    }
}

/// Which features of the two segments are closest.
pub fn edge_edge_type(ea0: P, ea1: P, eb0: P, eb1: P) -> u8 {
    let (u, v, w) = (s(ea1, ea0), s(eb1, eb0), s(ea0, eb0));
    let (a, b, cc, dd, e) = (d(u, u), d(u, v), d(v, v), d(u, w), d(v, w));
    let big_d = a * cc - b * b;
    if a == 0.0 && cc == 0.0 {
        return 0;
    } else if a == 0.0 {
        return 6;
    } else if cc == 0.0 {
        return 4;
    }
    let tol = 2.5e-16 * a * cc;
    let uv = c(u, v);
    let cross2 = d(uv, uv);
    if cross2 < tol {
        return parallel_edge_edge_type(ea0, ea1, eb0, eb1);
    }
    let mut default = 8;
    let sn = b * e - cc * dd;
    let (tn, td);
    if sn <= 0.0 {
        tn = e;
        td = cc;
        default = 6;
    } else if sn >= big_d {
        tn = e + b;
        td = cc;
        default = 7;
    } else {
        tn = a * e - b * dd;
        td = big_d;
    }
    if tn <= 0.0 {
        if -dd <= 0.0 {
            0
        } else if -dd >= a {
            2
        } else {
            4
        }
    } else if tn >= td {
        if -dd + b <= 0.0 {
            1
        } else if -dd + b >= a {
            3
        } else {
            5
        }
    } else {
        default
    }
}

fn line2(p: P, e0: P, e1: P) -> f64 {
    let x = c(s(e0, p), s(e1, p));
    let e = s(e1, e0);
    d(x, x) / d(e, e)
}

fn pp2(a: P, b: P) -> f64 {
    d(s(a, b), s(a, b))
}

pub fn pe_distance2(p: P, e0: P, e1: P, t: u8) -> f64 {
    match t {
        0 => pp2(p, e0),
        1 => pp2(p, e1),
        _ => line2(p, e0, e1),
    }
}

pub fn pt_distance2(p: P, t0: P, t1: P, t2: P, t: u8) -> f64 {
    let tt = [t0, t1, t2];
    match t {
        0..=2 => pp2(p, tt[t as usize]),
        3..=5 => {
            let k = (t - 3) as usize;
            line2(p, tt[k], tt[(k + 1) % 3])
        }
        _ => {
            let n = c(s(t1, t0), s(t2, t0));
            let h = d(s(p, t0), n);
            h * h / d(n, n)
        }
    }
}

pub fn ee_distance2(ea0: P, ea1: P, eb0: P, eb1: P, t: u8) -> f64 {
    match t {
        0 => pp2(ea0, eb0),
        1 => pp2(ea0, eb1),
        2 => pp2(ea1, eb0),
        3 => pp2(ea1, eb1),
        4 => line2(eb0, ea0, ea1),
        5 => line2(eb1, ea0, ea1),
        6 => line2(ea0, eb0, eb1),
        7 => line2(ea1, eb0, eb1),
        _ => {
            let n = c(s(ea1, ea0), s(eb1, eb0));
            let h = d(s(eb0, ea0), n);
            h * h / d(n, n)
        }
    }
}
