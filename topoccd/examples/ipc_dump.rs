//! Builds the collision set and the barrier potential of one configuration read from raw
//! files, and writes them out, for a comparison with another implementation (the IPC
//! toolkit) by a script.
//!
//! `cargo run --release -p topoccd --example ipc_dump -- DIR`: reads `DIR/x.f64`,
//! `DIR/rest.f64` (n x 3 little-endian f64), `DIR/faces.u32` (m x 3), `DIR/edges.u32` (free
//! edges, k x 2) and `DIR/params.json` (`dhat`, `dmin`, `kappa`, `area_weighting`); writes
//! `DIR/out.json` (the collisions, energy, minimum distance, timings), `DIR/grad.f64` and
//! the Hessians `DIR/hess_{none,clamp,abs}.{indptr,indices}.u64` / `.data.f64`.
//!
//! With `DIR/vel.f64` (n x 3) and `mu`, `eps_v` and `friction_kappa` in `params.json`, also
//! friction: the tangential collisions at `x` with the normal forces of the barrier of
//! stiffness `friction_kappa`, and the friction potential of the velocities `vel`: its
//! energy (in `out.json`), `DIR/friction_grad.f64` and the Hessians
//! `DIR/friction_hess_{none,clamp}.*` in the barrier's layout.

use std::path::Path;
use std::time::Instant;

use topoccd::ipc::friction::{FrictionCoefficients, FrictionPotential, TangentialCollisions};
use topoccd::ipc::{BarrierPotential, CollisionOptions, NormalCollisions, PsdProjection};
use topoccd::{Ccd, Configuration};

fn read_f64(p: &Path) -> Vec<f64> {
    std::fs::read(p)
        .unwrap_or_default()
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect()
}

fn read_u32(p: &Path) -> Vec<u32> {
    std::fs::read(p)
        .unwrap_or_default()
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().expect("4 bytes")))
        .collect()
}

fn write<T: Copy>(p: &Path, v: &[T], f: impl Fn(T) -> Vec<u8>) -> std::io::Result<()> {
    std::fs::write(p, v.iter().flat_map(|&t| f(t)).collect::<Vec<u8>>())
}

/// A CSR matrix as three raw files `{name}.indptr.u64`, `.indices.u64` and `.data.f64`.
fn write_csr(dir: &Path, name: &str, h: &topoccd::ipc::SparseMatrix) -> std::io::Result<()> {
    let (ip, ix, d) = h.csr();
    let as_u64 = |v: usize| (v as u64).to_le_bytes().to_vec();
    write(&dir.join(format!("{name}.indptr.u64")), ip, as_u64)?;
    write(&dir.join(format!("{name}.indices.u64")), ix, as_u64)?;
    write(&dir.join(format!("{name}.data.f64")), d, |v| {
        v.to_le_bytes().to_vec()
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).ok_or("usage: ipc_dump DIR")?;
    let dir = Path::new(&dir);
    let rows3 = |v: Vec<f64>| {
        v.chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect::<Vec<_>>()
    };
    let x = rows3(read_f64(&dir.join("x.f64")));
    let rest = rows3(read_f64(&dir.join("rest.f64")));
    let faces: Vec<[u32; 3]> = read_u32(&dir.join("faces.u32"))
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let edges: Vec<[u32; 2]> = read_u32(&dir.join("edges.u32"))
        .chunks_exact(2)
        .map(|c| [c[0], c[1]])
        .collect();
    let params: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("params.json"))?)?;
    let get = |k: &str| params[k].as_f64().unwrap_or(0.0);
    let options = CollisionOptions {
        dhat: get("dhat"),
        dmin: get("dmin"),
        use_area_weighting: params["area_weighting"].as_bool().unwrap_or(false),
        ..CollisionOptions::default()
    };
    let config = Configuration::new(&x, &faces, &edges)?;
    let mut ccd = Ccd::new();
    let t = Instant::now();
    let c = NormalCollisions::build(&mut ccd, &config, &rest, &options)?;
    let build_s = t.elapsed().as_secs_f64();
    let b = BarrierPotential::new(options.dhat, get("kappa"));
    let energy = b.energy(&c, &x);
    let grad = b.gradient(&c, &x);
    // Timing: energy + gradient, and the PSD Hessian, each the best of a few runs.
    let reps = 5;
    let (mut eg_s, mut h_s) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..reps {
        let t = Instant::now();
        let e = b.energy(&c, &x);
        let g = b.gradient(&c, &x);
        eg_s = eg_s.min(t.elapsed().as_secs_f64());
        std::hint::black_box((e, g));
        let t = Instant::now();
        let h = b.hessian(&c, &x, PsdProjection::Clamp);
        h_s = h_s.min(t.elapsed().as_secs_f64());
        std::hint::black_box(h);
    }
    write(&dir.join("grad.f64"), &grad, |v| v.to_le_bytes().to_vec())?;
    let mut nnz = serde_json::Map::new();
    for (name, m) in [
        ("none", PsdProjection::None),
        ("clamp", PsdProjection::Clamp),
        ("abs", PsdProjection::Abs),
    ] {
        let h = b.hessian(&c, &x, m);
        write_csr(dir, &format!("hess_{name}"), &h)?;
        nnz.insert(name.into(), h.nnz().into());
    }
    // Friction, when velocities are given.
    let vel = rows3(read_f64(&dir.join("vel.f64")));
    let mut friction = serde_json::Value::Null;
    if !vel.is_empty() {
        let barrier = BarrierPotential::new(options.dhat, get("friction_kappa"));
        let mu = FrictionCoefficients::uniform(get("mu"));
        let t = TangentialCollisions::build(&x, &c, &barrier, mu)?;
        let d = FrictionPotential::new(get("eps_v"))?;
        write(
            &dir.join("friction_grad.f64"),
            &d.gradient(&t, &vel)?,
            |v| v.to_le_bytes().to_vec(),
        )?;
        for (name, m) in [
            ("none", PsdProjection::None),
            ("clamp", PsdProjection::Clamp),
        ] {
            write_csr(
                dir,
                &format!("friction_hess_{name}"),
                &d.hessian(&t, &vel, m)?,
            )?;
        }
        friction = serde_json::json!({ "energy": d.energy(&t, &vel)?, "collisions": t.len() });
    }
    let out = serde_json::json!({
        "friction": friction,
        "vv": c.vv.iter().map(|v| (v.vertices, v.weight)).collect::<Vec<_>>(),
        "ev": c.ev.iter().map(|v| (v.edge, v.vertex, v.weight)).collect::<Vec<_>>(),
        "ee": c.ee.iter().map(|v| (v.a, v.b, v.kind as u8, v.eps_x, v.weight)).collect::<Vec<_>>(),
        "fv": c.fv.iter().map(|v| (v.triangle, v.vertex, v.weight)).collect::<Vec<_>>(),
        "energy": energy,
        "min_distance": c.compute_minimum_distance(&x),
        "nnz": nnz,
        "build_s": build_s,
        "energy_grad_s": eg_s,
        "psd_hessian_s": h_s,
    });
    std::fs::write(dir.join("out.json"), serde_json::to_string(&out)?)?;
    println!("{} collisions, energy {energy:e}", c.len());
    Ok(())
}
