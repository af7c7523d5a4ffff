//! `topoccd demo`: the main job on a built-in scene. Generates a small topology-changing scene in
//! memory (a bunny breaking a dragon into pieces, by default), runs every step with each method
//! and prints the paper's tables. Needs no file and no argument.

use std::path::Path;

use anyhow::Result;
use topoccd::io::sequence::step_from_frames;
use topoccd::Ccd;
use topoccd_scenes::paper::{generate, GenOptions, PaperScene};

use crate::cmd_bench::{bench_source, print_text, Source};
use crate::cmd_run::progress;
use crate::query_args::{MethodArg, QueryArgs};

/// Arguments of `topoccd demo` (all optional).
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene: nidus, nidus-cut, airbag, lion, bunny-dragon or crash.
    #[arg(long, default_value = "bunny-dragon", value_parser = parse_scene)]
    scene: PaperScene,
    /// Size relative to the paper's scene (1 = the paper's triangle count).
    #[arg(long, default_value_t = 0.05)]
    scale: f64,
    /// Frames to generate (steps = frames - 1).
    #[arg(long, default_value_t = 8)]
    frames: usize,
    /// Seed of the generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

fn parse_scene(s: &str) -> Result<PaperScene, String> {
    PaperScene::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = PaperScene::ALL.iter().map(|p| p.name()).collect();
        format!("unknown scene {s:?}; expected one of {}", names.join(", "))
    })
}

/// Runs the demo.
pub fn run(args: &Args) -> Result<()> {
    let options = GenOptions {
        scale: args.scale,
        frames: args.frames,
        seed: args.seed,
    };
    // Generate the frames in memory, building each step as soon as its second frame exists.
    let bar = progress(options.effective_frames(), "generating");
    let mut previous = None;
    let mut steps = Vec::new();
    let summary = generate(args.scene, &options, |k, mesh, parents| {
        if let Some(start) = previous.replace(mesh.clone()) {
            steps.push(step_from_frames(
                &start,
                mesh,
                parents,
                Path::new("(generated)"),
                k - 1,
            )?);
        }
        bar.inc(1);
        Ok::<(), anyhow::Error>(())
    })?;
    bar.finish_and_clear();
    eprintln!(
        "{}: {} frames, {}..{} triangles, {} topology changes, generated in {:.1} s",
        args.scene,
        summary.frames,
        summary.triangles_first,
        summary.triangles_last,
        summary.topology_changes,
        summary.seconds
    );
    let query = QueryArgs::default();
    let methods = [MethodArg::Bvh, MethodArg::Cluster, MethodArg::Brute];
    let name = format!("{} (scale {}, seed {})", args.scene, args.scale, args.seed);
    let (tables, _) = bench_source(
        &name,
        &Source::Memory(steps),
        &methods,
        &query.options()?,
        &mut Ccd::new(),
    )?;
    print_text(&tables);
    if !tables.agree {
        anyhow::bail!("the methods disagree (see above)");
    }
    println!("All three methods report the same pairs with the same times on every step.");
    Ok(())
}
