//! `topoccd gen SCENE OUT_DIR`: writes a generated frame sequence of one of the paper scenes,
//! or of a scene with free edges and points (`hair`, `funnel-particles`, `rod-rain`).

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use topoccd::io::sequence::write_frame;
use topoccd::{Ccd, Method, QueryOptions, Step};
use topoccd_scenes::codim::{codim_frames_scaled, CodimScene};
use topoccd_scenes::paper::{generate, GenOptions, GenSummary, PaperScene};

/// A scene `topoccd gen` writes.
#[derive(Clone, Copy, Debug)]
enum Scene {
    Paper(PaperScene),
    Codim(CodimScene),
}

/// Arguments of `topoccd gen`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The scene: nidus, nidus-cut, airbag, lion, bunny-dragon or crash; or, with free edges
    /// and points (written as PLY `edge` elements and vertices in no face): hair (a twisting
    /// bundle of hair strands), funnel-particles (particles poured into a funnel) or rod-rain
    /// (particles rained onto a grid of rods, pendulum rods swinging through it: contacts of
    /// all four kinds, vertex-edge and vertex-vertex among them).
    #[arg(value_parser = parse_scene)]
    scene: Scene,
    /// Folder to write the frames to (0000.ply, 0001.ply, ... and .parents files); created if
    /// missing, refused if it exists and is not empty.
    out_dir: PathBuf,
    /// Triangle count relative to the paper's, in (0, 4]: 0.1 writes a tenth (for hair,
    /// funnel-particles and rod-rain, the count of strands, particles and rods).
    #[arg(long, default_value_t = 1.0)]
    scale: f64,
    /// Number of frames (steps plus one), at least 2.
    #[arg(long, default_value_t = 10)]
    frames: usize,
    /// Seed of the random numbers: the same seed writes the same bytes.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print the summary as one JSON object (with the contacts of every step) instead of text.
    #[arg(long)]
    json: bool,
}

fn parse_scene(s: &str) -> Result<Scene, String> {
    if let Some(c) = CodimScene::from_name(s) {
        return Ok(Scene::Codim(c));
    }
    PaperScene::from_name(s).map(Scene::Paper).ok_or_else(|| {
        let names: Vec<&str> = (PaperScene::ALL.iter().map(|s| s.name()))
            .chain(CodimScene::ALL.iter().map(|s| s.name()))
            .collect();
        format!("unknown scene {s:?}; the scenes are {}", names.join(", "))
    })
}

/// Creates `dir`, or accepts it if it exists and is empty.
fn prepare(dir: &Path) -> Result<()> {
    if dir.exists() {
        if !dir.is_dir() {
            bail!("{} exists and is not a folder", dir.display());
        }
        let mut entries =
            fs::read_dir(dir).with_context(|| format!("cannot list {}", dir.display()))?;
        if entries.next().is_some() {
            bail!(
                "{} is not empty; refusing to write frames into it (choose a new or empty folder)",
                dir.display()
            );
        }
        return Ok(());
    }
    fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))
}

/// Runs `topoccd gen`.
pub fn run(args: &Args) -> Result<()> {
    if !(args.scale > 0.0 && args.scale <= 4.0) {
        bail!("--scale must be in (0, 4], got {}", args.scale);
    }
    if args.frames < 2 {
        bail!("--frames must be at least 2, got {}", args.frames);
    }
    prepare(&args.out_dir)?;
    let scene = match args.scene {
        Scene::Paper(scene) => scene,
        Scene::Codim(scene) => return run_codim(scene, args),
    };
    let options = GenOptions {
        scale: args.scale,
        frames: args.frames,
        seed: args.seed,
    };
    let bar = ProgressBar::new(args.frames as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {bar:30} {pos}/{len} frames {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_prefix(scene.name());
    let summary = generate(scene, &options, |k, mesh, parents| {
        let written = write_frame(&args.out_dir, k, mesh, parents);
        bar.set_message(format!("({} triangles)", mesh.triangles.len()));
        bar.inc(1);
        written.map(|_| ())
    });
    bar.finish_and_clear();
    let summary = summary.with_context(|| format!("writing {}", args.out_dir.display()))?;
    if args.json {
        println!("{}", serde_json::to_string(&summary)?);
    } else {
        println!("{}", summary_line(&summary, &args.out_dir));
    }
    Ok(())
}

/// `topoccd gen` of a scene with free edges and points: its frames (`--scale` scales the count
/// of strands, particles and rods), and a summary line with each step's contacts of every kind.
fn run_codim(scene: CodimScene, args: &Args) -> Result<()> {
    let frames = codim_frames_scaled(scene, args.frames, args.seed, args.scale);
    let mut ccd = Ccd::new();
    let mut contacts = Vec::new();
    for (k, mesh) in frames.iter().enumerate() {
        write_frame(&args.out_dir, k, mesh, &[])
            .with_context(|| format!("writing {}", args.out_dir.display()))?;
        if let Some(next) = frames.get(k + 1) {
            let step = Step::new(&mesh.positions, &next.positions, &mesh.triangles)?
                .with_edges(&mesh.edges)?;
            let r = ccd.query(&step, Method::Bvh, &QueryOptions::default())?;
            contacts.push([r.vf.len(), r.ee.len(), r.ve.len(), r.vv.len()]);
        }
    }
    let first = &frames[0];
    if args.json {
        let summary = serde_json::json!({
            "scene": scene.name(),
            "frames": frames.len(),
            "vertices": first.positions.len(),
            "triangles": first.triangles.len(),
            "edges": first.edges.len(),
            "contacts": contacts,
        });
        println!("{summary}");
    } else {
        println!(
            "{}: {} frames in {}; {} vertices, {} triangles, {} free edges; contacts per step \
             [vf, ee, ve, vv]: {:?}",
            scene.name(),
            frames.len(),
            args.out_dir.display(),
            first.positions.len(),
            first.triangles.len(),
            first.edges.len(),
            contacts
        );
    }
    Ok(())
}

/// The one-line summary of a generation.
fn summary_line(s: &GenSummary, dir: &Path) -> String {
    let (min, max) = s
        .contacts
        .iter()
        .fold((usize::MAX, 0), |(lo, hi), &c| (lo.min(c), hi.max(c)));
    let mean = s.contacts.iter().sum::<usize>() as f64 / s.contacts.len().max(1) as f64;
    format!(
        "{}: {} frames in {} in {:.1} s; triangles {} -> {}, vertices {} -> {}, {} of {} steps change the triangles, {} piece{}; contacts per step min {} mean {:.0} max {}: {:?}, of which collisions (not along fresh cracks) {:?}",
        s.scene,
        s.frames,
        dir.display(),
        s.seconds,
        s.triangles_first,
        s.triangles_last,
        s.vertices_first,
        s.vertices_last,
        s.topology_changes,
        s.contacts.len(),
        s.pieces,
        if s.pieces == 1 { "" } else { "s" },
        if s.contacts.is_empty() { 0 } else { min },
        mean,
        max,
        s.contacts,
        s.collisions,
    )
}
