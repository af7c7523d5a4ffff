//! The recording options of `run`, `step` and `demo`: `--rerun [OUT.rrd]` and its companions.
//! They exist in every build; without the cargo feature `rerun` they say how to get it.

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};

/// The default of `--rerun-max-primitives`: at most this many primitives (triangles of the
/// mesh, contacts, crack edges, volumes) are recorded per step.
pub const DEFAULT_MAX_PRIMITIVES: usize = 1_000_000;

/// Where and what to record for the Rerun viewer (flattened into the commands' arguments).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct RecordArgs {
    /// Record every step for the Rerun viewer (rerun.io): the mesh, the contacts coloured by
    /// time of impact with their points and normals, the earliest contact, fresh cracks and
    /// the step's figures, on a `step` timeline. With OUT.rrd, write that file; without, send
    /// it to a viewer (`rerun` on the PATH: `pip install rerun-sdk==0.36.3`). Put it after
    /// the inputs or write `--rerun=OUT.rrd`. Needs a build with the cargo feature `rerun`.
    #[arg(long, value_name = "OUT.rrd", num_args = 0..=1, help_heading = "Recording")]
    pub rerun: Option<Option<PathBuf>>,
    /// With --rerun: the most primitives (mesh triangles, contacts, crack edges, volumes)
    /// recorded per step; beyond it the step's recording leaves some out and says so (a
    /// warning in `topoccd/notes`, and on stderr).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_PRIMITIVES,
          value_parser = parse_primitives, help_heading = "Recording")]
    pub rerun_max_primitives: usize,
    /// With --rerun: record the clusters' swept boxes too (leaf and intermediate clusters,
    /// as the cluster method builds them), in `topoccd/volumes`.
    #[arg(long, help_heading = "Recording")]
    pub rerun_volumes: bool,
}

fn parse_primitives(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("{s:?} is not a count of at least 1")),
    }
}

/// Where a recording goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RecordTarget {
    /// A `.rrd` file.
    File(PathBuf),
    /// A viewer spawned from the PATH (or one already listening).
    Viewer,
}

impl RecordArgs {
    /// Where to record, `None` without `--rerun`. Refuses, before any work, a file that is
    /// not `.rrd`, that names an input, or that cannot be written.
    pub fn target(&self, inputs: &[&Path]) -> Result<Option<RecordTarget>> {
        let Some(rerun) = &self.rerun else {
            if self.rerun_volumes {
                bail!("--rerun-volumes needs --rerun");
            }
            return Ok(None);
        };
        let Some(path) = rerun else {
            return Ok(Some(RecordTarget::Viewer));
        };
        let is_rrd = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("rrd"));
        if !is_rrd {
            bail!(
                "{}: --rerun takes a file ending in .rrd (or nothing, for a viewer); put the \
                 inputs before --rerun, or write --rerun=OUT.rrd",
                path.display()
            );
        }
        if inputs.iter().any(|i| super::same_file(path, i)) {
            bail!(
                "{}: --rerun names an input; refusing to overwrite it",
                path.display()
            );
        }
        super::writable(path)?;
        Ok(Some(RecordTarget::File(path.clone())))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets() {
        let none = RecordArgs::default();
        assert_eq!(none.target(&[]).unwrap(), None);
        let viewer = RecordArgs {
            rerun: Some(None),
            ..RecordArgs::default()
        };
        assert_eq!(viewer.target(&[]).unwrap(), Some(RecordTarget::Viewer));
        let dir = std::env::temp_dir();
        let file = dir.join("topoccd-record-args-test.rrd");
        let to_file = RecordArgs {
            rerun: Some(Some(file.clone())),
            ..RecordArgs::default()
        };
        assert_eq!(to_file.target(&[]).unwrap(), Some(RecordTarget::File(file)));
        assert!(!dir.join("topoccd-record-args-test.rrd").exists());
        for bad in ["out.png", "no/such/folder/out.rrd"] {
            let args = RecordArgs {
                rerun: Some(Some(bad.into())),
                ..RecordArgs::default()
            };
            assert!(args.target(&[]).is_err(), "{bad}");
        }
        let volumes_alone = RecordArgs {
            rerun_volumes: true,
            ..RecordArgs::default()
        };
        assert!(volumes_alone.target(&[]).is_err());
        assert!(parse_primitives("0").is_err());
        assert_eq!(parse_primitives("12"), Ok(12));
    }
}
