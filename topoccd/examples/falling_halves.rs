//! A small simulator loop on topoccd: a sphere is cut in two halves, which fall onto a sheet.
//! Each step proposes the next positions, asks for the earliest time of impact, and advances
//! only to a safe fraction of it (a line search), so nothing ever passes through anything.
//!
//! The first step is the cut itself: the vertices on the cut are duplicated, and the copies
//! start where their parents are. Without the crack filter the two halves would "touch" at
//! t=0 all along the cut and the line search would never move; with it (the default) the first
//! step's earliest time is that of a real contact, or none.
//!
//! `cargo run --release -p topoccd --example falling_halves`

use topoccd::{Ccd, Method, Mode, QueryOptions, Step};

/// What one step of the simulation did.
#[derive(Clone, Debug)]
pub struct StepLog {
    /// The step's index.
    pub step: usize,
    /// Whether the step cut the sphere (a topology change).
    pub cut: bool,
    /// The earliest time of impact of the proposed motion, if any.
    pub earliest: Option<f64>,
    /// The fraction of the proposed motion taken.
    pub advanced: f64,
    /// Lowest height of the sphere's vertices after the step.
    pub lowest: f64,
}

/// A unit octahedron subdivided `levels` times and pushed onto the unit sphere. Every triangle
/// lies on one side of the plane x = 0 (the octahedron's edges lie in it).
fn sphere(levels: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut x: Vec<[f64; 3]> = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..levels {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(tris.len() * 4);
        let mut midpoint = |a: u32, b: u32, x: &mut Vec<[f64; 3]>| {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (x[a as usize], x[b as usize]);
                let m = [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]));
                let n = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                // Exact zeros stay zero: the cut plane x = 0 keeps its vertices.
                x.push(m.map(|c| c / n));
                x.len() as u32 - 1
            })
        };
        for [a, b, c] in tris {
            let (ab, bc, ca) = (
                midpoint(a, b, &mut x),
                midpoint(b, c, &mut x),
                midpoint(c, a, &mut x),
            );
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        tris = next;
    }
    (x, tris)
}

/// Cuts the sphere along x = 0: the triangles on the side x < 0 get copies of the vertices on
/// the plane. Returns the new triangles and the `[copy, original]` rows.
fn cut(x: &[[f64; 3]], tris: &[[u32; 3]]) -> (Vec<[u32; 3]>, Vec<[u32; 2]>) {
    let mut copy = vec![u32::MAX; x.len()];
    let mut parents = Vec::new();
    let mut next = Vec::with_capacity(tris.len());
    for tri in tris {
        let left = tri.iter().any(|&v| x[v as usize][0] < 0.0);
        next.push(if left {
            tri.map(|v| {
                if x[v as usize][0] != 0.0 {
                    return v;
                }
                if copy[v as usize] == u32::MAX {
                    copy[v as usize] = (x.len() + parents.len()) as u32;
                    parents.push([copy[v as usize], v]);
                }
                copy[v as usize]
            })
        } else {
            *tri
        });
    }
    (next, parents)
}

/// Runs the simulation for `steps` steps and returns what each step did.
pub fn simulate(steps: usize) -> Vec<StepLog> {
    let (ball, ball_tris) = sphere(3);
    // A square sheet of 2 x 8 x 8 triangles at height -2 under the sphere.
    let n = 9usize;
    let sheet: Vec<[f64; 3]> = (0..n * n)
        .map(|i| {
            let (a, b) = ((i % n) as f64, (i / n) as f64);
            [-4.0 + a, -2.0, -4.0 + b]
        })
        .collect();
    let offset = ball.len() as u32;
    let mut sheet_tris = Vec::new();
    for j in 0..n as u32 - 1 {
        for i in 0..n as u32 - 1 {
            let v = offset + j * n as u32 + i;
            sheet_tris.push([v, v + n as u32 + 1, v + 1]);
            sheet_tris.push([v, v + n as u32, v + n as u32 + 1]);
        }
    }
    // Vertex ids: the sphere, the sheet, then the copies made by the cut.
    let mut x: Vec<[f64; 3]> = ball.iter().chain(&sheet).copied().collect();
    let mut tris: Vec<[u32; 3]> = ball_tris.iter().chain(&sheet_tris).copied().collect();
    let (cut_tris, parents) = cut(&x, &ball_tris);
    let n_ball = ball.len();
    // Each half falls with its own velocity (per step), the sheet stays. 0: the right half
    // (with the vertices on the cut), 1: the left half (with their copies), 2: the sheet.
    let side = |v: usize| -> usize {
        if (n_ball..n_ball + sheet.len()).contains(&v) {
            2
        } else if v >= n_ball + sheet.len() || ball[v][0] < 0.0 {
            1
        } else {
            0
        }
    };
    let mut velocity = [[0.1, -0.23, 0.0], [-0.12, -0.31, 0.04], [0.0, 0.0, 0.0]];
    let mut ccd = Ccd::new();
    let options = QueryOptions {
        mode: Mode::Earliest,
        ..QueryOptions::default()
    };
    let mut log = Vec::with_capacity(steps);
    for k in 0..steps {
        let cutting = k == 0;
        if cutting {
            tris = cut_tris.iter().chain(&sheet_tris).copied().collect();
        }
        let count = x.len() + if cutting { parents.len() } else { 0 };
        // The proposed positions at the end of the step: new vertices start at their parent.
        let mut start = x.clone();
        if cutting {
            start.extend(parents.iter().map(|&[_, p]| x[p as usize]));
        }
        let x1: Vec<[f64; 3]> = (0..count)
            .map(|v| {
                let d = velocity[side(v)];
                let p = start[v];
                [p[0] + d[0], p[1] + d[1], p[2] + d[2]]
            })
            .collect();
        let step = if cutting {
            Step::with_parents(&x, &x1, &tris, &parents)
        } else {
            Step::new(&x, &x1, &tris)
        }
        .expect("the simulation's steps are valid");
        let report = ccd
            .query(&step, Method::Bvh, &options)
            .expect("the options are valid");
        let earliest = report.earliest_toi();
        // The halves in the earliest contact (the report holds the earliest pair(s)) stop.
        let tri = |f: u32| step.triangles()[f as usize];
        let hit: Vec<usize> = report
            .vf
            .iter()
            .flat_map(|c| [c.vertex, tri(c.face)[0]])
            .chain(report.ee.iter().flat_map(|c| [c.a[0], c.b[0]]))
            .map(|v| side(v as usize))
            .collect();
        drop(step);
        // Line search: go to 80% of the earliest time of impact.
        let advanced = earliest.map_or(1.0, |t| 0.8 * t);
        x = start
            .iter()
            .zip(&x1)
            .map(|(s, e)| [0, 1, 2].map(|c| s[c] + advanced * (e[c] - s[c])))
            .collect();
        for s in hit {
            if s < 2 {
                velocity[s] = [0.0, 0.0, 0.0];
            }
        }
        let lowest = x[..n_ball]
            .iter()
            .chain(&x[n_ball + sheet.len()..])
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min);
        log.push(StepLog {
            step: k,
            cut: cutting,
            earliest,
            advanced,
            lowest,
        });
    }
    log
}

fn main() {
    for s in simulate(12) {
        println!(
            "step {:2}{}: earliest toi {:<22} advanced {:.3} of the step, lowest point y = {:.4}",
            s.step,
            if s.cut { " (cut)" } else { "      " },
            s.earliest.map_or("none".to_string(), |t| format!("{t:.6}")),
            s.advanced,
            s.lowest
        );
    }
}
