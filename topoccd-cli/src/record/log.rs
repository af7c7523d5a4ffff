//! A [`StepScene`] into Rerun's archetypes, on the `step` timeline (feature `rerun`).

use anyhow::{bail, Context, Result};
use re_sdk::blueprint::{
    Blueprint, BlueprintPanel, Horizontal, SelectionPanel, Spatial3DView, TextLogView, TimePanel,
    TimeSeriesView, Vertical,
};
use re_sdk::{RecordingStream, RecordingStreamBuilder};
use re_sdk_types::archetypes::{
    Arrows3D, Boxes3D, LineStrips3D, Mesh3D, Points3D, Scalars, TextLog,
};
use re_sdk_types::blueprint::components::PanelState;
use re_sdk_types::components::TextLogLevel;

use super::scene::StepScene;
use super::RERUN_VERSION;
use crate::common::RecordTarget;
use crate::render::palette;

/// The recording's application id (the viewer groups recordings by it).
const APP_ID: &str = "topoccd";

/// The colour of the earliest contact's marker.
const EARLIEST: [u8; 3] = [230, 20, 140];

/// The viewer's default layout: the 3D view beside the plots of the figures and the notes, the
/// side panels collapsed (the Python helpers' `topoccd.rerun.blueprint()` is the same).
fn blueprint() -> Blueprint {
    let scene = Spatial3DView::new("contacts")
        .with_origin("/topoccd")
        .with_contents(["+ /topoccd/**", "- /topoccd/stats/**", "- /topoccd/notes"]);
    let seconds = TimeSeriesView::new("seconds by phase").with_origin("/topoccd/stats/seconds");
    let work = TimeSeriesView::new("candidates and contacts")
        .with_origin("/topoccd/stats")
        .with_contents([
            "+ /topoccd/stats/candidates/**",
            "+ /topoccd/stats/contacts",
        ]);
    let notes = TextLogView::new("notes").with_origin("/topoccd/notes");
    let side = Vertical::new([seconds.into(), work.into(), notes.into()]);
    Blueprint::new(Horizontal::new([scene.into(), side.into()]).with_column_shares([2.0, 1.0]))
        .with_blueprint_panel(BlueprintPanel::from_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::from_state(PanelState::Collapsed))
        .with_time_panel(
            TimePanel::new()
                .with_state(PanelState::Collapsed)
                .with_timeline("step"),
        )
}

/// An open recording stream.
pub struct Stream {
    rec: RecordingStream,
    target: RecordTarget,
    /// The mesh's triangles as last logged: a step with the same ones logs its positions only
    /// (the viewer keeps the latest triangles), a third of the mesh's bytes.
    last_triangles: Option<Vec<[u32; 3]>>,
}

/// Whether an executable named `name` is on the PATH.
fn on_path(name: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|paths| {
        std::env::split_paths(&paths).any(|dir| {
            let p = dir.join(name);
            p.is_file()
                && std::fs::metadata(&p).is_ok_and(|m| {
                    use std::os::unix::fs::PermissionsExt;
                    m.permissions().mode() & 0o111 != 0
                })
        })
    })
}

impl Stream {
    /// Opens a recording to a file or to a viewer spawned from the PATH.
    pub fn open(target: &RecordTarget, name: &str) -> Result<Self> {
        // `enabled(true)`: the environment variable RERUN=off does not silently drop it.
        let builder = RecordingStreamBuilder::new(APP_ID)
            .recording_name(name)
            .enabled(true)
            .with_default_blueprint(blueprint());
        let rec = match target {
            RecordTarget::File(path) => builder
                .save(path)
                .with_context(|| format!("{}: cannot write the recording", path.display()))?,
            RecordTarget::Viewer => {
                if !on_path("rerun") {
                    bail!(
                        "--rerun without a file sends the recording to a Rerun viewer, but no \
                         `rerun` is on the PATH. Install one with `pip install \
                         rerun-sdk=={RERUN_VERSION}` (it provides the `rerun` command), or \
                         write a file with --rerun OUT.rrd and open it later with `rerun OUT.rrd`"
                    );
                }
                builder
                    .spawn()
                    .context("cannot start the Rerun viewer (`rerun` on the PATH)")?
            }
        };
        Ok(Self {
            rec,
            target: target.clone(),
            last_triangles: None,
        })
    }

    /// Records one step at `step` = `k`.
    pub fn step(&mut self, k: usize, s: &StepScene, summary: &str) -> Result<()> {
        self.log_step(k, s, summary)
            .with_context(|| format!("--rerun: cannot record step {k}"))
    }

    fn log_step(&mut self, k: usize, s: &StepScene, summary: &str) -> Result<()> {
        let rec = &self.rec;
        rec.set_time_sequence("step", k as i64);
        match &s.mesh {
            Some((positions, triangles))
                if self.last_triangles.as_deref() == Some(triangles.as_slice()) =>
            {
                rec.log(
                    "topoccd/mesh",
                    &Mesh3D::update_fields().with_vertex_positions(positions.iter().copied()),
                )?
            }
            Some((positions, triangles)) => {
                rec.log(
                    "topoccd/mesh",
                    &Mesh3D::new(positions.iter().copied())
                        .with_triangle_indices(triangles.iter().copied())
                        .with_albedo_factor(palette::NEUTRAL),
                )?;
                self.last_triangles = Some(triangles.clone());
            }
            // An empty mesh: the previous step's does not linger.
            None => {
                rec.log(
                    "topoccd/mesh",
                    &Mesh3D::new(std::iter::empty::<[f32; 3]>())
                        .with_triangle_indices(std::iter::empty::<[u32; 3]>()),
                )?;
                self.last_triangles = None;
            }
        }
        // The contact faces as one mesh of separate triangles, so each has its own colour.
        let corners = s.faces.iter().flatten().copied();
        let corner_colors = s.face_colors.iter().flat_map(|c| [*c; 3]);
        let n = s.faces.len() as u32;
        rec.log(
            "topoccd/contacts/faces",
            &Mesh3D::new(corners)
                .with_triangle_indices((0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]))
                .with_vertex_colors(corner_colors),
        )?;
        rec.log(
            "topoccd/contacts/vertices",
            &Points3D::new(s.vertices.iter().copied())
                .with_colors(s.vertex_colors.iter().copied())
                .with_radii([s.radius * 1.5]),
        )?;
        rec.log(
            "topoccd/contacts/edges",
            &LineStrips3D::new(s.edges.iter().copied())
                .with_colors(s.edge_colors.iter().copied())
                .with_radii([s.radius]),
        )?;
        rec.log(
            "topoccd/contacts/points",
            &Points3D::new(s.points.iter().copied())
                .with_colors(s.point_colors.iter().copied())
                .with_radii([s.radius])
                .with_labels(s.labels.iter().map(String::as_str))
                .with_show_labels(false),
        )?;
        rec.log(
            "topoccd/contacts/normals",
            &Arrows3D::from_vectors(s.normals.iter().copied())
                .with_origins(s.points.iter().copied())
                .with_colors(s.point_colors.iter().copied()),
        )?;
        let (earliest, label): (Vec<[f32; 3]>, Vec<&str>) = match &s.earliest {
            Some((p, l)) => (vec![*p], vec![l.as_str()]),
            None => (Vec::new(), Vec::new()),
        };
        rec.log(
            "topoccd/earliest",
            &Points3D::new(earliest)
                .with_colors([EARLIEST])
                .with_radii([s.radius * 4.0])
                .with_labels(label),
        )?;
        rec.log(
            "topoccd/cracks/edges",
            &LineStrips3D::new(s.crack_edges.iter().copied())
                .with_colors([palette::CRACK])
                .with_radii([s.radius * 0.75]),
        )?;
        rec.log(
            "topoccd/cracks/vertices",
            &Points3D::new(s.crack_vertices.iter().copied())
                .with_colors([palette::CRACK])
                .with_radii([s.radius]),
        )?;
        for (path, boxes, color) in [
            ("topoccd/volumes/leaves", &s.leaf_boxes, [40, 100, 210]),
            (
                "topoccd/volumes/intermediate",
                &s.intermediate_boxes,
                [90, 90, 90],
            ),
        ] {
            if s.volumes {
                rec.log(
                    path,
                    &Boxes3D::from_mins_and_sizes(
                        boxes.iter().map(|b| b.0),
                        boxes.iter().map(|b| b.1),
                    )
                    .with_colors([color]),
                )?;
            }
        }
        for (name, value) in &s.scalars {
            rec.log(format!("topoccd/stats/{name}"), &Scalars::single(*value))?;
        }
        rec.log(
            "topoccd/notes",
            &TextLog::new(format!("step {k}: {summary}")).with_level(TextLogLevel::INFO),
        )?;
        for note in &s.notes {
            rec.log(
                "topoccd/notes",
                &TextLog::new(format!("step {k}: {note}")).with_level(TextLogLevel::WARN),
            )?;
        }
        Ok(())
    }

    /// Flushes the recording and closes it.
    pub fn finish(self) -> Result<()> {
        self.rec
            .flush_blocking()
            .with_context(|| match &self.target {
                RecordTarget::File(p) => format!("{}: cannot write the recording", p.display()),
                RecordTarget::Viewer => "cannot send the recording to the viewer".to_string(),
            })?;
        self.rec.disconnect();
        Ok(())
    }
}
