//! Times the barrier potential over one frame's collision set, for profilers and quick
//! timings: energy, gradient, the plain Hessian and the PSD-projected Hessian (clamp), each
//! the minimum CPU time of REPS, and the per-collision figures.
//!
//! Usage: `potential_probe FRAME.ply [REPS]`. `dhat` is 1e-3 x the bounding-box diagonal,
//! rest = the frame, ipctk's defaults; one thread. Then the PSD Hessian's parts: the block
//! pattern, the local Hessians (distance derivatives and the barrier's chain rule), their
//! projection, and the assembly (scatter into the blocks and the CSR layout).

use topoccd::ipc::{BarrierPotential, CollisionOptions, NormalCollisions, PsdProjection};
use topoccd::{Ccd, Configuration};
use topoccd_benches::cpu_seconds;

fn best<R>(reps: usize, mut f: impl FnMut() -> R) -> f64 {
    let mut t = f64::INFINITY;
    for _ in 0..reps {
        let s = cpu_seconds();
        std::hint::black_box(f());
        t = t.min(cpu_seconds() - s);
    }
    t
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: potential_probe FRAME [REPS]");
        std::process::exit(2);
    };
    let reps: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .expect("a thread pool");
    let mesh = topoccd_benches::read_frame(path);
    let dhat = topoccd_benches::dhat_of(&mesh.positions);
    let x = mesh.positions.as_slice();
    let config = Configuration::new(x, mesh.triangles.as_slice(), &mesh.edges).expect("a frame");
    let options = CollisionOptions {
        dhat,
        ..Default::default()
    };
    let c = NormalCollisions::build(&mut Ccd::new(), &config, x, &options).expect("a set");
    let b = BarrierPotential::new(dhat, 1.0);
    let n = c.len() as f64;
    println!(
        "{path}: {} collisions (vv {}, ev {}, ee {}, fv {})",
        c.len(),
        c.vv.len(),
        c.ev.len(),
        c.ee.len(),
        c.fv.len()
    );
    let te = best(reps, || b.energy(&c, x));
    let tg = best(reps, || b.gradient(&c, x));
    let th = best(reps, || b.hessian(&c, x, PsdProjection::None));
    let tp = best(reps, || b.hessian(&c, x, PsdProjection::Clamp));
    let h = b.hessian(&c, x, PsdProjection::Clamp);
    for (name, t) in [
        ("energy", te),
        ("gradient", tg),
        ("hessian", th),
        ("hessian_psd", tp),
        ("e+g+psd", te + tg + tp),
    ] {
        println!(
            "{name:12} {:9.3} ms  {:7.3} us/collision",
            t * 1e3,
            t / n * 1e6
        );
    }
    println!("nnz {}", h.nnz());
    // The PSD Hessian's parts, each the minimum over REPS.
    let mut parts = [f64::INFINITY; 4];
    for _ in 0..reps {
        let t = b.hessian_parts(&c, x, PsdProjection::Clamp, cpu_seconds);
        for k in 0..4 {
            parts[k] = parts[k].min(t[k]);
        }
    }
    let [pattern, locals, projected, whole] = parts;
    for (name, t) in [
        ("pattern", pattern),
        ("locals", locals),
        ("projection", projected - locals),
        ("assembly", whole - pattern - projected),
    ] {
        println!(
            "  {name:10} {:9.3} ms  {:7.3} us/collision",
            t * 1e3,
            t / n * 1e6
        );
    }
}
