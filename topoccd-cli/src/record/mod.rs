//! Recordings for the Rerun viewer (`--rerun`): one step at a time on a `step` timeline.
//!
//! The entities, all under `topoccd/`:
//! - `mesh`: the mesh at t=0, its triangles as they are in this step;
//! - `contacts/faces`, `contacts/vertices`, `contacts/edges`: the colliding features at t=0,
//!   coloured by time of impact (red at 0, blue at 1);
//! - `contacts/points`, `contacts/normals`: each contact's point at its time of impact and
//!   its normal (the report's geometry), labelled with its pair and time;
//! - `earliest`: the earliest contact, marked;
//! - `cracks/edges`, `cracks/vertices`: the edges along the cracks the step opens, the
//!   vertices it adds;
//! - `volumes/leaves`, `volumes/intermediate`: the clusters' swept boxes (`--rerun-volumes`);
//! - `stats/...`: the step's figures as scalars (seconds by phase, candidates, contacts);
//! - `notes`: one line per step, and a warning when the cap left something out.
//!
//! The Python helpers (`topoccd.rerun`) write the same layout.

pub mod scene;

#[cfg(feature = "rerun")]
mod log;

use anyhow::Result;
use topoccd::{Ccd, Method, Report, Step};

use crate::common::{RecordArgs, RecordTarget};
use scene::{SceneOptions, StepScene};

/// The version of Rerun this build records with (`pip install rerun-sdk==` it for a viewer).
pub const RERUN_VERSION: &str = "0.36.3";

/// A recording under way (or nothing, without `--rerun`).
pub struct Recorder {
    #[cfg(feature = "rerun")]
    stream: log::Stream,
    options: SceneOptions,
    warned: bool,
}

impl Recorder {
    /// Opens the recording `args` ask for, `None` without `--rerun`. Fails with a clear message
    /// without the `rerun` feature, or when a viewer is asked for and none is on the PATH.
    pub fn open(
        args: &RecordArgs,
        name: &str,
        inputs: &[&std::path::Path],
    ) -> Result<Option<Self>> {
        let Some(target) = args.target(inputs)? else {
            return Ok(None);
        };
        let options = SceneOptions {
            max_primitives: args.rerun_max_primitives,
            volumes: args.rerun_volumes,
        };
        Self::start(&target, name, options).map(Some)
    }

    #[cfg(feature = "rerun")]
    fn start(target: &RecordTarget, name: &str, options: SceneOptions) -> Result<Self> {
        Ok(Self {
            stream: log::Stream::open(target, name)?,
            options,
            warned: false,
        })
    }

    #[cfg(not(feature = "rerun"))]
    fn start(_target: &RecordTarget, _name: &str, _options: SceneOptions) -> Result<Self> {
        anyhow::bail!(
            "--rerun needs a topoccd built with the cargo feature `rerun` (this one was not; \
             the feature is on by default): `cargo install --path topoccd-cli` or `cargo \
             build --release -p topoccd-cli` (Rust 1.95 or newer; it records with Rerun \
             {RERUN_VERSION})"
        )
    }

    /// Records step `k`, queried by `ccd` with `method` into `report`. Says on stderr (once)
    /// when the cap leaves something out.
    pub fn step(
        &mut self,
        k: usize,
        step: &Step,
        report: &Report,
        ccd: &Ccd,
        method: Method,
        summary: &str,
    ) -> Result<()> {
        let scene = StepScene::new(step, report, ccd, method, self.options);
        if !scene.notes.is_empty() && !self.warned {
            self.warned = true;
            eprintln!(
                "warning: --rerun: step {k}: {} (said in the recording's topoccd/notes; later \
                 steps are not warned of here)",
                scene.notes.join("; ")
            );
        }
        self.log(k, &scene, summary)
    }

    #[cfg(feature = "rerun")]
    fn log(&mut self, k: usize, scene: &StepScene, summary: &str) -> Result<()> {
        self.stream.step(k, scene, summary)
    }

    #[cfg(not(feature = "rerun"))]
    fn log(&mut self, _k: usize, _scene: &StepScene, _summary: &str) -> Result<()> {
        Ok(())
    }

    /// Writes out what is buffered and closes the recording.
    pub fn finish(self) -> Result<()> {
        #[cfg(feature = "rerun")]
        self.stream.finish()?;
        Ok(())
    }
}
