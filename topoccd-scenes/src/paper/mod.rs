//! Generators for scenes of the kinds and sizes of the paper's five benchmarks (section 5):
//! frame sequences, streamed frame by frame, deterministic for a seed.
//!
//! | scene          | paper triangles | what happens |
//! |----------------|-----------------|--------------|
//! | `nidus`        | 32,798          | a lumpy, lobed vascular blob bends so its lobes press together |
//! | `nidus-cut`    | 32,798          | the same blob while a cut advances through it |
//! | `airbag`       | 9,076           | a folded sewn bag inflates and unfolds into a wheel (a torus) |
//! | `lion`         | 1.6M            | a lion-like body explodes into pieces that hit each other |
//! | `bunny-dragon` | 0.25M (to 0.27M)| a bunny breaks a dragon-like body into thousands of pieces |
//! | `crash`        | 1.1M (to 1.2M)  | a thin-shell car-like body is crushed against a wall, tearing |
//!
//! Triangle counts scale with [`GenOptions::scale`] (`0.1` gives a tenth). The meshes are made
//! here (the paper's files are not public): star-shaped blobs with lobes and smooth noise on a
//! cube-sphere (embedded by construction), a torus, sewn sheets, a grid wall.
//!
//! # Motion model
//!
//! Every scene is a set of *pieces* (see `world.rs`), each moving one of three ways during a
//! step (the time unit is one step):
//! - *soft*: every vertex follows a smooth, scene-specific displacement field evaluated at its
//!   rest position (bending lobes, inflation and folding, the crush of a car);
//! - *rigid*: velocity and spin, plus gravity (pieces broken off);
//! - *static*: walls and the unbroken part of breakable bodies.
//!
//! Topology changes happen at the start of a step. A fragment (one cell of a breadth-first
//! geodesic partition of the surface, see `fracture.rs`) breaks off by duplicating the vertices
//! it shares with the rest of the mesh — the copies get new ids, appended, each listed in the
//! frame's parents with the vertex it copies — and re-indexing its triangles; it becomes a
//! rigid piece. A cut splits the vertices along its path the same way without detaching
//! anything. Triangle counts stay constant: fractures and cuts re-index triangles, they do not
//! add caps, so `bunny-dragon` and `crash` keep their first frame's count (the paper's grow by
//! 8%).
//!
//! # Collisions
//!
//! The first frame is free of intersections: the meshes are built apart, then each scene runs
//! its motion forward with `Mode::Earliest` queries until the first contact and starts halfway
//! to it (so step 0 collides). After each proposed step the generator queries it with
//! [`Ccd`](topoccd::Ccd) in `Mode::All`, stores it as proposed (its contacts included)
//! and changes the motion of the following steps: soft vertices that touched stop for good,
//! rigid pieces bounce with restitution, a fast impact on a breakable body breaks the touched
//! fragment off (see `response.rs`). So surfaces cross by at most about one step's motion.
//!
//! ```
//! use topoccd_scenes::paper::{generate_frames, GenOptions, PaperScene};
//! let options = GenOptions { scale: 0.02, frames: 3, seed: 7 };
//! let (frames, summary) = generate_frames(PaperScene::Airbag, &options);
//! assert_eq!(frames.len(), 3);
//! assert_eq!(summary.contacts.len(), 2);
//! assert!(summary.contacts.iter().all(|&c| c > 0));
//! ```

mod airbag;
mod crash;
mod driver;
mod explode;
mod fracture;
mod nidus;
mod response;
mod shapes;
mod world;

use std::fmt;

use topoccd::io::Mesh;

/// The six paper scenes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub enum PaperScene {
    /// A vascular blob under large deformation (33K triangles).
    Nidus,
    /// The same blob, being cut (33K triangles).
    NidusCut,
    /// A sewn bag inflating against a wheel (9K triangles).
    Airbag,
    /// A lion-like body exploding into pieces (1.6M triangles).
    Lion,
    /// A bunny breaking a dragon-like body into thousands of pieces (0.25M triangles).
    BunnyDragon,
    /// A car-like thin shell crushed against a wall, tearing (1.1M triangles).
    Crash,
}

impl PaperScene {
    /// All scenes, in the paper's order.
    pub const ALL: [PaperScene; 6] = [
        PaperScene::Nidus,
        PaperScene::NidusCut,
        PaperScene::Airbag,
        PaperScene::Lion,
        PaperScene::BunnyDragon,
        PaperScene::Crash,
    ];

    /// The scene's name on the command line: `nidus`, `nidus-cut`, `airbag`, `lion`,
    /// `bunny-dragon` or `crash`.
    pub fn name(self) -> &'static str {
        match self {
            PaperScene::Nidus => "nidus",
            PaperScene::NidusCut => "nidus-cut",
            PaperScene::Airbag => "airbag",
            PaperScene::Lion => "lion",
            PaperScene::BunnyDragon => "bunny-dragon",
            PaperScene::Crash => "crash",
        }
    }

    /// The scene named `name` (see [`PaperScene::name`]).
    ///
    /// ```
    /// use topoccd_scenes::paper::PaperScene;
    /// assert_eq!(PaperScene::from_name("bunny-dragon"), Some(PaperScene::BunnyDragon));
    /// assert_eq!(PaperScene::from_name("dragon"), None);
    /// ```
    pub fn from_name(name: &str) -> Option<Self> {
        PaperScene::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The paper's triangle count (first frame) for the scene (table 2).
    pub fn paper_triangles(self) -> usize {
        match self {
            PaperScene::Nidus | PaperScene::NidusCut => 32_798,
            PaperScene::Airbag => 9_076,
            PaperScene::Lion => 1_600_000,
            PaperScene::BunnyDragon => 250_000,
            PaperScene::Crash => 1_100_000,
        }
    }

    /// Whether the scene changes its triangles as it runs (cut, fracture, tearing).
    pub fn changes_topology(self) -> bool {
        !matches!(self, PaperScene::Nidus | PaperScene::Airbag)
    }
}

impl fmt::Display for PaperScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Options of [`generate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GenOptions {
    /// Triangle count relative to the paper's, in `[1e-4, 4]` (values outside are clamped;
    /// NaN counts as 1). The motion is the same at every scale, only the resolution changes.
    pub scale: f64,
    /// Number of frames (steps plus one), at least 2 (smaller values count as 2).
    pub frames: usize,
    /// Seed of the random numbers; the same options give the same frames, bit for bit.
    pub seed: u64,
}

impl Default for GenOptions {
    /// Scale 1, 10 frames, seed 1.
    fn default() -> Self {
        Self {
            scale: 1.0,
            frames: 10,
            seed: 1,
        }
    }
}

impl GenOptions {
    /// The scale actually used (see [`GenOptions::scale`]).
    pub fn effective_scale(&self) -> f64 {
        if self.scale.is_nan() {
            1.0
        } else {
            self.scale.clamp(1e-4, 4.0)
        }
    }

    /// The frame count actually used (see [`GenOptions::frames`]).
    pub fn effective_frames(&self) -> usize {
        self.frames.max(2)
    }
}

/// What a generation produced.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GenSummary {
    /// The scene.
    pub scene: PaperScene,
    /// Frames generated.
    pub frames: usize,
    /// Vertices of the first frame.
    pub vertices_first: usize,
    /// Triangles of the first frame.
    pub triangles_first: usize,
    /// Vertices of the last frame.
    pub vertices_last: usize,
    /// Triangles of the last frame.
    pub triangles_last: usize,
    /// Colliding vertex-face and edge-edge pairs of each step, as found by
    /// [`Ccd::query`](topoccd::Ccd::query) with `Method::Bvh` in `Mode::All` on exactly
    /// the step a reader of the frames gets (with the generators' iteration budget of 20,000
    /// boxes per elementary test; a pair that exhausts it counts as a contact).
    pub contacts: Vec<usize>,
    /// The contacts of each step that are collisions: all but those between features meeting
    /// along a fresh crack or cut (which coincide at the start of the step, as the parents
    /// file puts them).
    pub collisions: Vec<usize>,
    /// Steps whose triangles differ from the previous frame's.
    pub topology_changes: usize,
    /// Pieces at the end (connected parts moving separately: objects and fragments).
    pub pieces: usize,
    /// Wall-clock time of the whole generation (meshes, pre-roll, steps, the sink's work), in
    /// seconds: the only field that varies between runs.
    pub seconds: f64,
}

/// Generates a scene, handing frame `k` to `sink(k, mesh, parents)` in order, `k = 0, 1, ...`
/// (`parents`: the `(new, parent)` vertex pairs of the frame, empty for frame 0), so only the
/// current frame is in memory. Stops at the sink's first error and returns it.
///
/// To write a sequence, pass [`write_frame`](topoccd::io::sequence::write_frame):
///
/// ```
/// use topoccd::io::sequence::{write_frame, Sequence};
/// use topoccd_scenes::paper::{generate, GenOptions, PaperScene};
/// let dir = std::env::temp_dir().join(format!("topoccd-doc-gen-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let options = GenOptions { scale: 0.02, frames: 3, seed: 1 };
/// let summary = generate(PaperScene::NidusCut, &options, |k, mesh, parents| {
///     write_frame(&dir, k, mesh, parents).map(|_| ())
/// })?;
/// assert_eq!(Sequence::open(&dir)?.steps(), summary.frames - 1);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn generate<E>(
    scene: PaperScene,
    options: &GenOptions,
    mut sink: impl FnMut(usize, &Mesh, &[(u32, u32)]) -> Result<(), E>,
) -> Result<GenSummary, E> {
    let scale = options.effective_scale();
    let frames = options.effective_frames();
    let seed = options.seed;
    let sink: &mut driver::Sink<'_, E> = &mut sink;
    let start = std::time::Instant::now();
    let mut summary = match scene {
        PaperScene::Nidus => nidus::run(false, scale, frames, seed, sink),
        PaperScene::NidusCut => nidus::run(true, scale, frames, seed, sink),
        PaperScene::Airbag => airbag::run(scale, frames, seed, sink),
        PaperScene::Lion => explode::run_lion(scale, frames, seed, sink),
        PaperScene::BunnyDragon => explode::run_bunny_dragon(scale, frames, seed, sink),
        PaperScene::Crash => crash::run(scale, frames, seed, sink),
    }?;
    summary.seconds = start.elapsed().as_secs_f64();
    Ok(summary)
}

/// One generated frame, as handed to the sink of [`generate`].
#[derive(Clone, Debug, PartialEq)]
pub struct GeneratedFrame {
    /// Positions and triangles.
    pub mesh: Mesh,
    /// `(new, parent)` pairs of the vertices new in this frame.
    pub parents: Vec<(u32, u32)>,
}

/// [`generate`] into memory: every frame, then the summary. For small scales (tests).
///
/// ```
/// use topoccd_scenes::paper::{generate_frames, GenOptions, PaperScene};
/// let options = GenOptions { scale: 0.02, frames: 3, seed: 2 };
/// let (frames, summary) = generate_frames(PaperScene::Nidus, &options);
/// assert_eq!(frames[0].mesh.triangles.len(), summary.triangles_first);
/// ```
pub fn generate_frames(
    scene: PaperScene,
    options: &GenOptions,
) -> (Vec<GeneratedFrame>, GenSummary) {
    let mut frames = Vec::new();
    let result = generate(scene, options, |_, mesh, parents| {
        frames.push(GeneratedFrame {
            mesh: mesh.clone(),
            parents: parents.to_vec(),
        });
        Ok::<(), std::convert::Infallible>(())
    });
    let summary = match result {
        Ok(summary) => summary,
        Err(never) => match never {},
    };
    (frames, summary)
}

/// The first frame's triangle count of a scene, computed from the meshes alone (no motion, no
/// query): cheap enough for scale 1.
///
/// ```
/// use topoccd_scenes::paper::{initial_triangles, PaperScene};
/// let n = initial_triangles(PaperScene::Airbag, 1.0);
/// assert!((n as f64 - 9_076.0).abs() < 0.25 * 9_076.0);
/// ```
pub fn initial_triangles(scene: PaperScene, scale: f64) -> usize {
    let options = GenOptions {
        scale,
        ..GenOptions::default()
    };
    let scale = options.effective_scale();
    match scene {
        PaperScene::Nidus | PaperScene::NidusCut => nidus::triangles(scale),
        PaperScene::Airbag => airbag::triangles(scale),
        PaperScene::Lion => explode::lion_triangles(scale),
        PaperScene::BunnyDragon => explode::bunny_dragon_triangles(scale),
        PaperScene::Crash => crash::triangles(scale),
    }
}
