//! `topoccd render FRAME [--step NEXT_FRAME] [--color clusters|contacts|objects] [--pairs FILE]
//! [--camera AZIMUTH,ELEVATION] [--fit mesh|contacts] [--up x|y|z] [--size WxH] [--indexed]
//! --out FILE.png`: a picture of a mesh
//! or of a step, for debugging by looking.
//!
//! With `--step`, FRAME is the step's t=0 and NEXT_FRAME its t=1 (NEXT_FRAME's triangles; new
//! vertices start at their parent's position when a `.parents` file sits beside NEXT_FRAME, as
//! in [`topoccd::io::sequence`]). The picture always shows the step's *start*: the positions at
//! t=0 with the step's triangles. The clusters are those of the whole step (t=0 to t=1).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::str::FromStr;

use anyhow::{anyhow, bail, Context, Result};
use topoccd::broad::cluster::{cluster, ClusterOptions};

use crate::common::*;
use crate::query_args::GrowthArg;
use topoccd::io::{frame_number, read_mesh, sequence::step_between_loose};
use topoccd::math::DVec3;
use topoccd::mesh::Topology;
use topoccd::Step;

use crate::render::annotate::{annotate, band_height, LegendEntry};
use crate::render::camera::{UpAxis, View};
use crate::render::contacts::{contact_triangles, read_pairs, Contact};
use crate::render::encode::{encode_png, PngColors};
use crate::render::paint::{
    connected_components, paint_clusters, paint_contacts, paint_objects, TriangleStyle,
};
use crate::render::palette::{self, categorical};
use crate::render::{draw, supersampling, DrawOptions};

/// Largest picture side, in pixels.
const MAX_SIDE: u32 = 8192;
/// Largest picture, in pixels (keeps the buffers under about 200 MB).
const MAX_PIXELS: u64 = 16 << 20;

/// How the triangles are coloured.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ColorMode {
    /// Leaf clusters in distinct colours; intermediate-cluster boundaries (and the mesh's
    /// boundary) outlined in black, as in the paper's figures 4 and 5.
    Clusters,
    /// Triangles involved in a contact (from --pairs) in red over light grey; where other
    /// surfaces hide them they show through, faded.
    Contacts,
    /// Connected components (through shared vertices) in distinct colours.
    Objects,
}

/// What the camera frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Fit {
    /// The whole mesh.
    Mesh,
    /// The triangles involved in contacts (needs --color contacts): they fill half of the
    /// picture, the mesh around them is clipped at its edges. The whole mesh if there are none.
    Contacts,
}

/// `--up`: an axis, or chosen from the data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum UpArg {
    /// Chosen from the data (see `--up`).
    Auto,
    /// `+x` up.
    X,
    /// `+y` up.
    Y,
    /// `+z` up.
    Z,
}

/// The up axis `--up auto` picks for a mesh at `pos0` (and `pos1` at the step's end), with the
/// reason in words:
/// 1. a sheet-like mesh (its bounding box's thinnest side at most half the next one): the
///    thinnest axis (a cloth lying flat, a floor);
/// 2. otherwise, when the vertices' mean motion from t=0 to t=1 points down one axis (at
///    least 80% of it along `-x`, `-y` or `-z`): that axis (things falling under gravity);
/// 3. otherwise z, the convention of the shared scenes and of `topoccd gen`.
pub fn auto_up(pos0: &[DVec3], pos1: &[DVec3]) -> (UpAxis, String) {
    let axes = [(UpAxis::X, "x"), (UpAxis::Y, "y"), (UpAxis::Z, "z")];
    let finite = pos0.iter().filter(|p| p.is_finite());
    let (lo, hi) = finite.fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    if lo.x <= hi.x {
        let extent = (hi - lo).to_array();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| extent[a].total_cmp(&extent[b]));
        let (k, thinnest, next) = (order[0], extent[order[0]], extent[order[1]]);
        if next > 0.0 && thinnest <= 0.5 * next {
            return (
                axes[k].0,
                format!(
                    "the mesh is a sheet, thinnest along {} ({thinnest:.3} against {next:.3})",
                    axes[k].1
                ),
            );
        }
        let n = pos0.len().min(pos1.len());
        if n > 0 {
            let mean = (0..n)
                .map(|i| pos1[i] - pos0[i])
                .filter(|d| d.is_finite())
                .fold(DVec3::ZERO, |a, d| a + d)
                / n as f64;
            let m = mean.to_array();
            let (k, down) = m
                .iter()
                .copied()
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("three axes");
            let largest = extent[order[2]];
            if -down > 1e-9 * largest && -down >= 0.8 * mean.length() {
                return (
                    axes[k].0,
                    format!(
                        "the mesh falls along -{} (mean motion {:.3?})",
                        axes[k].1, m
                    ),
                );
            }
        }
    }
    (
        UpAxis::Z,
        "no sheet and no fall: z, the convention of the shared scenes and of topoccd gen".into(),
    )
}

/// `--camera AZIMUTH,ELEVATION`, in degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraAngles {
    /// Degrees around the up axis, any finite value.
    pub azimuth: f64,
    /// Degrees above the horizontal plane, `[-90, 90]`.
    pub elevation: f64,
}

impl FromStr for CameraAngles {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let usage = "expected AZIMUTH,ELEVATION in degrees, e.g. 35,25";
        let (a, e) = s.split_once(',').ok_or_else(|| format!("'{s}': {usage}"))?;
        let number = |x: &str| x.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let (Some(azimuth), Some(elevation)) = (number(a), number(e)) else {
            return Err(format!("'{s}': {usage}"));
        };
        if !(-90.0..=90.0).contains(&elevation) {
            return Err(format!("'{s}': the elevation must be in [-90, 90]"));
        }
        Ok(Self { azimuth, elevation })
    }
}

/// `--size WxH`, in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Width, `1..=8192`.
    pub width: u32,
    /// Height, `1..=8192`.
    pub height: u32,
}

impl FromStr for Size {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("'{s}': expected WIDTHxHEIGHT in pixels, e.g. 1024x768");
        let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
        let (width, height) = (
            w.trim().parse::<u32>().map_err(|_| bad())?,
            h.trim().parse::<u32>().map_err(|_| bad())?,
        );
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(format!("'{s}': each side must be in 1..={MAX_SIDE}"));
        }
        if u64::from(width) * u64::from(height) > MAX_PIXELS {
            return Err(format!("'{s}': at most {MAX_PIXELS} pixels"));
        }
        Ok(Self { width, height })
    }
}

/// Arguments of `topoccd render`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Mesh file (PLY or OBJ). The picture shows its positions (the step's t=0 with --step).
    frame: PathBuf,
    #[command(flatten)]
    loose: LooseArgs,
    /// Next frame (PLY or OBJ): FRAME to NEXT_FRAME is the step, with NEXT_FRAME's triangles;
    /// the clusters are computed over the step, the picture shows its start (t=0).
    #[arg(long, value_name = "NEXT_FRAME")]
    step: Option<PathBuf>,
    /// What the colours show.
    #[arg(long, value_enum, default_value_t = ColorMode::Clusters)]
    color: ColorMode,
    /// How leaf clusters grow (for `--color clusters`), as `topoccd step --method cluster`.
    #[arg(long, value_enum, default_value_t = GrowthArg::default_growth())]
    growth: GrowthArg,
    /// Contacts for --color contacts: lines `vf,VERTEX,FACE,TOI` or `ee,A0,A1,B0,B1,TOI`.
    #[arg(long, value_name = "FILE")]
    pairs: Option<PathBuf>,
    /// View direction in degrees: azimuth around the up axis, elevation above the horizon
    /// (orthographic; the whole mesh is framed).
    #[arg(
        long,
        value_name = "AZIMUTH,ELEVATION",
        default_value = "35,25",
        allow_hyphen_values = true
    )]
    camera: CameraAngles,
    /// What the camera frames.
    #[arg(long, value_enum, default_value_t = Fit::Mesh)]
    fit: Fit,
    /// World axis pointing up in the picture. `auto` chooses it from the data: the axis along
    /// which the mesh is thinnest when it is a sheet (thinner than a tenth of its largest
    /// side); otherwise, with --step, the axis of the vertices' mean motion when one axis
    /// carries most of it (falling under gravity); otherwise y. The choice is printed.
    #[arg(long, value_enum, default_value_t = UpArg::Auto)]
    up: UpArg,
    /// Picture size in pixels.
    #[arg(long, value_name = "WxH", default_value = "1024x768")]
    size: Size,
    /// Output PNG file (overwritten if it exists; never one of the input meshes).
    #[arg(long, value_name = "FILE.png")]
    out: PathBuf,
    /// Store at most 256 colours (a palette PNG, about a third of the size; colours are
    /// approximated when the picture has more), e.g. for pictures kept in a repository.
    #[arg(long)]
    indexed: bool,
}

/// Runs the command.
pub fn run(args: &Args) -> Result<ExitCode> {
    check_output(args)?;
    if args.pairs.is_some() && args.color != ColorMode::Contacts {
        bail!("--pairs is only used with --color contacts");
    }
    if args.fit == Fit::Contacts && args.color != ColorMode::Contacts {
        bail!("--fit contacts needs --color contacts");
    }
    let start = read_mesh(&args.frame)?;
    let step = match &args.step {
        Some(next_path) => {
            let end = read_mesh(next_path)?;
            let k = frame_number(&args.frame).unwrap_or(0) as usize;
            step_between_loose(&start, &end, next_path, k, args.loose.loose)?
        }
        None => {
            let positions: Vec<DVec3> = start
                .positions
                .iter()
                .map(|&p| DVec3::from_array(p))
                .collect();
            Step::new(positions.clone(), positions, start.triangles)
                .map_err(|e| anyhow!("{}: {e}", args.frame.display()))?
        }
    };
    let topo = Topology::new(step.triangles(), step.vertex_count());
    let faces = step.triangles().len();
    let moves = args.step.is_some() && step.pos0() != step.pos1();

    let mut focus: Option<Vec<bool>> = None;
    let mut show_through: Option<Vec<bool>> = None;
    let mut legend: Vec<LegendEntry> = Vec::new();
    let entry = |color: [u8; 3], label: String| LegendEntry {
        color,
        line: false,
        label,
    };
    let (styles, what): (Vec<TriangleStyle>, &str) = match args.color {
        ColorMode::Objects => {
            let (component, count) = connected_components(step.triangles(), step.vertex_count());
            eprintln!("objects: {count} connected components over {faces} triangles");
            legend.push(entry(
                categorical(0),
                format!("one colour per connected piece ({count})"),
            ));
            (paint_objects(&component), "connected pieces")
        }
        ColorMode::Clusters => {
            let options = ClusterOptions {
                phi_filter: args.growth == GrowthArg::Paper,
                ..ClusterOptions::default()
            };
            let clustering = cluster(&step, &topo, &options);
            let s = &clustering.stats;
            eprintln!(
                "clusters: {} leaf clusters, {} intermediate clusters over {} triangles \
                 ({:.1} triangles per leaf, {:.1} per intermediate cluster)",
                s.leaves,
                s.intermediates,
                s.triangles,
                s.triangles_per_leaf,
                s.triangles_per_intermediate
            );
            legend.push(entry(
                categorical(0),
                format!("one colour per leaf cluster ({})", s.leaves),
            ));
            legend.push(LegendEntry {
                color: palette::OUTLINE,
                line: true,
                label: format!(
                    "boundaries of intermediate clusters ({}) and of the mesh",
                    s.intermediates
                ),
            });
            (paint_clusters(&clustering, &topo), "clusters")
        }
        ColorMode::Contacts => {
            let contacts: Vec<Contact> = match &args.pairs {
                Some(path) => read_pairs(path, step.vertex_count(), faces)?,
                // Without --pairs: the step's own contacts, from the whole-step query, crack
                // contacts included (they are told apart below).
                None => {
                    let options = topoccd::QueryOptions {
                        crack_filter: false,
                        ..topoccd::QueryOptions::default()
                    };
                    let report = topoccd::query(&step, topoccd::Method::default(), &options)?;
                    eprintln!(
                        "{} vf and {} ee contacts in the step (crack contacts included)",
                        report.vf.len(),
                        report.ee.len()
                    );
                    let vf = report.vf.iter().map(|c| Contact::VertexFace {
                        vertex: c.vertex,
                        face: c.face,
                        toi: c.toi,
                    });
                    let ee = report.ee.iter().map(|c| Contact::EdgeEdge {
                        a: c.a,
                        b: c.b,
                        toi: c.toi,
                    });
                    vf.chain(ee).collect()
                }
            };
            let canon = canonical_vertices(step.parents(), step.vertex_count());
            let (crack, real): (Vec<Contact>, Vec<Contact>) = contacts
                .iter()
                .partition(|c| is_crack_contact(c, &canon, step.triangles()));
            let involved = contact_triangles(&real, &topo, faces);
            let cracked = contact_triangles(&crack, &topo, faces);
            let styles = contact_styles(&real, &involved);
            eprintln!(
                "crack contacts (features joined through a split vertex): {} of {}, involving \
                 {} more triangles",
                crack.len(),
                contacts.len(),
                cracked
                    .iter()
                    .zip(&involved)
                    .filter(|&(&c, &r)| c && !r)
                    .count()
            );
            let styles: Vec<TriangleStyle> = styles
                .into_iter()
                .zip(involved.iter().zip(&cracked))
                .map(|(s, (&r, &c))| {
                    if c && !r {
                        TriangleStyle::plain(palette::CRACK)
                    } else {
                        s
                    }
                })
                .collect();
            let any: Vec<bool> = involved
                .iter()
                .zip(&cracked)
                .map(|(&r, &c)| r || c)
                .collect();
            legend.push(entry(
                palette::CONTACT,
                format!("in a contact ({})", plural(real.len(), "pair")),
            ));
            if !crack.is_empty() {
                legend.push(entry(
                    palette::CRACK,
                    format!(
                        "in crack contacts only ({} joined through a split vertex, \
                         touching by construction: not collisions)",
                        plural(crack.len(), "pair")
                    ),
                ));
            }
            legend.push(entry(palette::NEUTRAL, "no contact".into()));
            if args.fit == Fit::Contacts {
                focus = Some(if involved.contains(&true) {
                    involved
                } else {
                    any.clone()
                });
            }
            show_through = Some(any);
            (styles, "contacts")
        }
    };
    if moves {
        legend.push(LegendEntry {
            color: palette::GHOST,
            line: true,
            label: "outline at the end of the step (t=1)".into(),
        });
    }
    if show_through.is_some() {
        legend.push(entry(
            palette::mix(palette::NEUTRAL, palette::CONTACT, 0.35),
            "faded: behind nearer surfaces".into(),
        ));
    }

    let (up, reason) = match args.up {
        UpArg::Auto => auto_up(step.pos0(), step.pos1()),
        UpArg::X => (UpAxis::X, "--up x".into()),
        UpArg::Y => (UpAxis::Y, "--up y".into()),
        UpArg::Z => (UpAxis::Z, "--up z".into()),
    };
    eprintln!("up axis: {} ({reason})", up_name(up));
    let view = View {
        azimuth_deg: args.camera.azimuth,
        elevation_deg: args.camera.elevation,
        up,
    };
    let Size { width, height } = args.size;
    let band = band_height(&legend, width, height);
    let mesh_height = height - band;
    let options = DrawOptions {
        view,
        width,
        height: mesh_height,
        samples: supersampling(width, mesh_height),
        focus: focus.as_deref(),
        show_through: show_through.as_deref(),
        ghost: moves.then(|| step.pos1()),
    };
    let mesh_picture = draw(step.pos0(), step.triangles(), &styles, &options);
    let mut picture = image::RgbImage::from_pixel(width, height, image::Rgb(palette::BACKGROUND));
    image::imageops::replace(&mut picture, &mesh_picture, 0, i64::from(band));
    let title = match &args.step {
        Some(next) => format!(
            "{} to {}: {what} at the start of the step (t=0), {} up",
            file_name(&args.frame),
            file_name(next),
            up_name(up)
        ),
        None => format!("{}: {what}, {} up", file_name(&args.frame), up_name(up)),
    };
    annotate(&mut picture, band, &title, &legend);
    let colors = if args.indexed {
        PngColors::Indexed
    } else {
        PngColors::TrueColor
    };
    let bytes = encode_png(&picture, colors)
        .with_context(|| format!("{}: cannot encode", args.out.display()))?;
    std::fs::write(&args.out, bytes)
        .with_context(|| format!("{}: cannot write", args.out.display()))?;
    eprintln!("wrote {} ({width}x{height})", args.out.display());
    Ok(ExitCode::SUCCESS)
}

/// Styles for `--color contacts` from a list of contacts (read from `--pairs`, or computed by a
/// whole-step query; crack contacts left out) and the triangles they involve (see
/// [`contact_triangles`]): those in red over grey. Prints the counts to stderr.
pub fn contact_styles(contacts: &[Contact], involved: &[bool]) -> Vec<TriangleStyle> {
    let faces = involved.len();
    let vf = contacts
        .iter()
        .filter(|c| matches!(c, Contact::VertexFace { .. }))
        .count();
    eprintln!(
        "contacts: {vf} vertex-face and {} edge-edge contacts involve {} of {faces} triangles",
        contacts.len() - vf,
        involved.iter().filter(|&&hit| hit).count()
    );
    paint_contacts(involved)
}

/// The name of an axis.
fn up_name(up: UpAxis) -> &'static str {
    match up {
        UpAxis::X => "x",
        UpAxis::Y => "y",
        UpAxis::Z => "z",
    }
}

/// The file name of a path, for titles.
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

/// Each vertex's original: a new vertex's parent (followed up to its root), itself otherwise.
/// `parents` holds `[child, parent]` rows, as [`Step::parents`].
pub fn canonical_vertices(parents: &[[u32; 2]], vertices: usize) -> Vec<u32> {
    let mut canon: Vec<u32> = (0..vertices as u32).collect();
    for &[child, parent] in parents {
        if (child as usize) < vertices && (parent as usize) < vertices {
            canon[child as usize] = parent;
        }
    }
    // Follow chains (a copy of a copy), at most `vertices` links (cycles cannot loop forever).
    for v in 0..vertices {
        let mut root = canon[v];
        for _ in 0..vertices {
            let next = canon[root as usize];
            if next == root {
                break;
            }
            root = next;
        }
        canon[v] = root;
    }
    canon
}

/// Whether a contact is a crack contact: its two features share a vertex once every new
/// vertex is identified with its parent (see [`canonical_vertices`]); such features touch by
/// construction along a fresh cut or crack, and the library's crack filter drops them.
pub fn is_crack_contact(contact: &Contact, canon: &[u32], triangles: &[[u32; 3]]) -> bool {
    let c = |v: u32| canon.get(v as usize).copied().unwrap_or(v);
    match *contact {
        Contact::VertexFace { vertex, face, .. } => triangles
            .get(face as usize)
            .is_some_and(|f| f.iter().any(|&w| c(w) == c(vertex))),
        Contact::EdgeEdge { a, b, .. } => a.iter().any(|&x| b.iter().any(|&y| c(x) == c(y))),
    }
}

/// Refuses an output that is not a `.png` file or that is one of the input files.
fn check_output(args: &Args) -> Result<()> {
    let out = &args.out;
    let is_png = out
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    if !is_png {
        bail!("{}: --out must name a .png file", out.display());
    }
    let inputs = std::iter::once(&args.frame)
        .chain(&args.step)
        .chain(&args.pairs);
    for input in inputs {
        if same_file(out, input) {
            bail!(
                "{}: --out names an input file; refusing to overwrite it",
                out.display()
            );
        }
    }
    writable(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn camera_angles() {
        let c: CameraAngles = "-30, 12.5".parse().unwrap();
        assert_eq!((c.azimuth, c.elevation), (-30.0, 12.5));
        assert!("35".parse::<CameraAngles>().is_err());
        assert!("a,b".parse::<CameraAngles>().is_err());
        assert!("35,91".parse::<CameraAngles>().is_err());
        assert!("inf,0".parse::<CameraAngles>().is_err());
        assert!("NaN,0".parse::<CameraAngles>().is_err());
    }

    #[test]
    fn sizes() {
        assert_eq!(
            "1024x768".parse::<Size>(),
            Ok(Size {
                width: 1024,
                height: 768
            })
        );
        assert_eq!(
            "1X1".parse::<Size>(),
            Ok(Size {
                width: 1,
                height: 1
            })
        );
        for bad in ["0x10", "10", "x", "-1x5", "9000x10", "8192x8192"] {
            assert!(bad.parse::<Size>().is_err(), "{bad}");
        }
    }

    #[test]
    fn auto_up_axis() {
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        // A sheet thinnest along z, along x, and a cube falling along -y, and a still cube.
        let sheet = [v(0.0, 0.0, 0.0), v(4.0, 3.0, 0.1)];
        assert_eq!(auto_up(&sheet, &sheet).0, UpAxis::Z);
        let wall = [v(0.0, 0.0, 0.0), v(0.2, 3.0, 4.0)];
        assert_eq!(auto_up(&wall, &wall).0, UpAxis::X);
        let cube = [v(0.0, 0.0, 0.0), v(1.0, 1.0, 1.0)];
        let fallen = cube.map(|p| p - DVec3::Y * 0.5);
        let (up, why) = auto_up(&cube, &fallen);
        assert_eq!(up, UpAxis::Y, "{why}");
        // Rising is no fall: the default, z.
        let risen = cube.map(|p| p + DVec3::Y * 0.5);
        assert_eq!(auto_up(&cube, &risen).0, UpAxis::Z);
        assert_eq!(auto_up(&cube, &cube).0, UpAxis::Z);
        assert_eq!(auto_up(&[], &[]).0, UpAxis::Z);
    }

    #[test]
    fn crack_contacts_share_a_vertex_through_the_parents() {
        // Vertex 4 copies 1, vertex 5 copies 4 (a chain); triangle 0 = (0, 1, 2).
        let canon = canonical_vertices(&[[4, 1], [5, 4]], 6);
        assert_eq!(canon, [0, 1, 2, 3, 1, 1]);
        let tris = [[0, 1, 2], [3, 4, 5]];
        let vf = |vertex, face| Contact::VertexFace {
            vertex,
            face,
            toi: 0.0,
        };
        assert!(is_crack_contact(&vf(5, 0), &canon, &tris));
        assert!(!is_crack_contact(&vf(3, 0), &canon, &tris));
        let ee = |a, b| Contact::EdgeEdge { a, b, toi: 0.0 };
        assert!(is_crack_contact(&ee([4, 3], [1, 0]), &canon, &tris));
        // 5 is a copy of 1, which neither 3, 2 nor 0 is.
        assert!(!is_crack_contact(&ee([3, 2], [0, 5]), &canon, &tris));
        assert!(!is_crack_contact(&ee([3, 2], [0, 1]), &canon, &tris));
    }
}
