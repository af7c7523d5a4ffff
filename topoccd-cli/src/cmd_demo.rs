//! `topoccd demo`: the main job on a built-in scene. Generates a small topology-changing scene in
//! memory (a bunny breaking a dragon into pieces, by default), runs every step with each method
//! and prints the paper's tables. Needs no file and no argument.

use std::path::Path;

use anyhow::Result;
use topoccd::io::sequence::step_from_frames;
use topoccd::Ccd;
use topoccd_scenes::paper::{generate, GenOptions, PaperScene};

use crate::common::*;
use crate::query_args::{MethodArg, QueryArgs};
use crate::record::Recorder;

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
    #[command(flatten)]
    record: RecordArgs,
}

fn parse_scene(s: &str) -> Result<PaperScene, String> {
    PaperScene::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = PaperScene::ALL.iter().map(|p| p.name()).collect();
        format!("unknown scene {s:?}; expected one of {}", names.join(", "))
    })
}

/// Runs the demo.
pub fn run(args: &Args) -> Result<()> {
    let name = format!("topoccd demo --scene {} --scale {}", args.scene, args.scale);
    let mut recorder = Recorder::open(&args.record, &name, &[])?;
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
    let name = format!("{} (scale {}, seed {})", args.scene, args.scale, args.seed);
    println!(
        "{name}: {} generated in {:.1} s, {}.",
        plural(summary.frames, "frame"),
        summary.seconds,
        plural(steps.len(), "step"),
    );
    println!(
        "{}",
        mesh_sentence(
            &steps,
            summary.topology_changes,
            summary.vertices_first,
            summary.vertices_last,
            summary.pieces
        )
    );
    let query = QueryArgs::default();
    let options = query.options()?;
    let methods = [MethodArg::Bvh, MethodArg::Cluster, MethodArg::Brute];
    let mut ccd = Ccd::new();
    // What was detected, in plain words: the default method's contacts of every step.
    let mut found = Found::default();
    // The recording shows each contact's point and normal (the tables are timed without).
    let mut found_options = options;
    found_options.geometry |= recorder.is_some();
    for (k, step) in steps.iter().enumerate() {
        let method = topoccd::Method::Bvh;
        let report = ccd.query(step, method, &found_options)?;
        if let Some(recorder) = &mut recorder {
            let summary = StepOut::new(step, method, found_options.mode, &report, false).text();
            recorder.step(k, step, &report, &ccd, method, &summary)?;
        }
        found.add(k, &report);
    }
    if let Some(recorder) = recorder {
        recorder.finish()?;
    }
    let mut ccds = vec![Ccd::new(); methods.len()];
    let (tables, _) = bench_source(&name, &Source::Memory(steps), &methods, &options, &mut ccds)?;
    print_text(&tables);
    if let Some(line) = verdict(&tables) {
        println!("{line}");
    }
    println!();
    println!("{}", found.sentence());
    if !tables.agree {
        anyhow::bail!("the methods disagree (see above)");
    }
    println!("All three methods report the same pairs with the same times on every step.");
    Ok(())
}

/// Speedups within this factor of 1 are a tie: timings of a few milliseconds vary by more.
const TIE: f64 = 0.05;

/// One line on when and why the cluster method wins or loses against the bvh baseline here,
/// from the measured figures: what grouping the triangles into clusters cost a step, what the
/// clusters saved on hierarchies, traversal and tests, and how many leaf clusters came near
/// another one (those get a hierarchy built). `None` unless both methods ran.
fn verdict(t: &crate::common::tables::InputTables) -> Option<String> {
    let row = |name: &str| t.methods.iter().find(|m| m.method == name);
    let (bvh, cluster) = (row("bvh")?, row("cluster")?);
    let speedup = t.speedup_cluster_over_bvh?;
    let ms = |s: f64| s * 1e3;
    let grouping: f64 = (cluster.seconds.iter())
        .filter(|(p, _)| matches!(*p, "clustering" | "merging"))
        .map(|(_, s)| s)
        .sum();
    // What the clusters' hierarchies, traversal and tests cost, against bvh's whole query.
    let rest = cluster.total - grouping;
    let saved = bvh.total - rest;
    let near = match &t.clusters {
        Some(c) if c.leaf > 0.0 => format!(
            "; {:.0} of its {:.0} leaf clusters a step came near another and got a hierarchy",
            c.lazy_bvhs, c.leaf
        ),
        _ => String::new(),
    };
    let triangles = thousands(t.triangles[1]);
    let figures = format!(
        "grouping the triangles costs it {:.2} ms a step and the clusters save {:.2} ms on \
         hierarchies, traversal and tests ({:.2} ms against bvh's {:.2} ms){near}",
        ms(grouping),
        ms(saved),
        ms(rest),
        ms(bvh.total)
    );
    Some(if speedup > 1.0 + TIE {
        format!(
            "Why cluster wins here ({speedup:.2}x, {triangles} triangles): {figures}; it wins \
             because the clusters save more than their grouping costs."
        )
    } else if speedup < 1.0 - TIE {
        let cause = if saved <= 0.0 {
            "the clusters save nothing here, so the grouping is pure cost"
        } else {
            "the saving is smaller than the grouping's cost"
        };
        format!(
            "Why cluster loses here ({speedup:.2}x, {triangles} triangles): {figures}; \
             {cause}. Cluster wins only where its clusters save more than their grouping costs."
        )
    } else {
        format!(
            "Why cluster and bvh tie here ({speedup:.2}x, {triangles} triangles): {figures}; \
             the saving about pays for the grouping. Cluster wins only where its clusters save \
             more than their grouping costs."
        )
    })
}

/// What the steps' meshes are, in plain words: triangle counts, how many steps change the
/// mesh and how, the pieces at the end.
fn mesh_sentence(
    steps: &[topoccd::Step<'static>],
    changes: usize,
    vertices_first: usize,
    vertices_last: usize,
    pieces: usize,
) -> String {
    let counts = steps.iter().map(|s| s.triangles().len());
    let (lo, hi) = (counts.clone().min().unwrap_or(0), counts.max().unwrap_or(0));
    let triangles = if lo == hi {
        format!("{} throughout", plural(lo, "triangle"))
    } else {
        format!("{} to {} triangles", thousands(lo), thousands(hi))
    };
    let how = if lo == hi && vertices_last > vertices_first {
        " (vertices are split, triangles are kept)"
    } else {
        ""
    };
    let changed = if changes == 0 {
        "no step cuts or breaks the mesh".to_string()
    } else {
        format!(
            "{} {} the mesh{how}",
            plural(changes, "step"),
            if changes == 1 {
                "cuts or breaks"
            } else {
                "cut or break"
            }
        )
    };
    format!(
        "{triangles}; {changed}; {} vertices at the start, {} at the end; {} at the end.",
        thousands(vertices_first),
        thousands(vertices_last),
        plural(pieces, "separate piece")
    )
}

/// The contacts found over the steps.
#[derive(Default)]
struct Found {
    vf: usize,
    ee: usize,
    steps: usize,
    with_contacts: usize,
    earliest: Option<(f64, usize)>,
}

impl Found {
    fn add(&mut self, k: usize, report: &topoccd::Report) {
        self.steps += 1;
        self.vf += report.vf.len();
        self.ee += report.ee.len();
        self.with_contacts += usize::from(!report.vf.is_empty() || !report.ee.is_empty());
        let tois = report
            .vf
            .iter()
            .map(|c| c.toi)
            .chain(report.ee.iter().map(|c| c.toi));
        if let Some(t) = tois.min_by(f64::total_cmp) {
            if self.earliest.is_none_or(|(e, _)| t < e) {
                self.earliest = Some((t, k));
            }
        }
    }

    /// One line: `Found N vertex-face and M edge-edge contacts over K steps; ...`.
    fn sentence(&self) -> String {
        let mut s = format!(
            "Found {} and {} over {} ({} with at least one contact)",
            plural(self.vf, "vertex-face contact"),
            plural(self.ee, "edge-edge contact"),
            plural(self.steps, "step"),
            thousands(self.with_contacts)
        );
        match self.earliest {
            Some((t, k)) => {
                s.push_str(&format!(
                "; the earliest at t={t:.4} of step {k}{} (t runs from 0 to 1 within each step).",
                if t == 0.0 { ", touching at its start" } else { "" }
            ))
            }
            None => s.push_str(": nothing touches."),
        }
        s
    }
}
