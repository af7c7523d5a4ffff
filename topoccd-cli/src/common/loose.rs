//! `--loose-vertices points|ignore`: what every command reads a file's vertices in no face and
//! no edge as (the library's one rule, `topoccd::io::with_file_primitives`).

use topoccd::io::LooseVertices;

/// The option, flattened into the arguments of every command that reads frames.
#[derive(clap::Args, Debug, Clone, Copy, Default)]
pub struct LooseArgs {
    /// What vertices in no face and no edge are: `points`, free points (particles), tested
    /// against faces, free edges and each other (the default, the IPC toolkit's rule, with or
    /// without edges in the file); or `ignore`, leftovers in no pair.
    #[arg(long = "loose-vertices", value_name = "points|ignore", default_value_t = LooseVertices::Points, value_parser = parse_loose)]
    pub loose: LooseVertices,
}

fn parse_loose(s: &str) -> Result<LooseVertices, String> {
    s.parse()
        .map_err(|e: topoccd::io::UnknownLooseVertices| e.to_string())
}

/// The warning of `check` and `proximity` on a file's loose vertices, `None` without any.
pub fn loose_warning(path: &std::path::Path, loose: &[u32], how: LooseVertices) -> Option<String> {
    let first = loose.first()?;
    let (read, other) = match how {
        LooseVertices::Points => ("are read as free points (particles)", "ignore"),
        LooseVertices::Ignore => ("are ignored (--loose-vertices ignore)", "points"),
    };
    Some(format!(
        "warning: {}: {} vertices in no face and no edge (the first: {first}) {read}; \
         `--loose-vertices {other}` reads them otherwise",
        path.display(),
        loose.len(),
    ))
}
