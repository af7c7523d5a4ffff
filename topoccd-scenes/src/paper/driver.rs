//! The loop every paper scene runs: topology change, proposed motion, the query, the response,
//! and the frame handed to the sink.

use super::response::{hits, respond, Break, Hit};
use super::world::World;
use super::{GenSummary, PaperScene};
use glam::DVec3;
use topoccd::io::Mesh;
use topoccd::{Ccd, Method, Mode, QueryOptions, Report, Step};

/// Where the frames go: `sink(k, mesh, parents)` for frame `k`.
pub(crate) type Sink<'a, E> = dyn FnMut(usize, &Mesh, &[(u32, u32)]) -> Result<(), E> + 'a;

/// What a scene adds to the common loop.
pub(crate) trait Script {
    /// Topology changes at the start of step `k` (fragments breaking off, a cut advancing).
    /// New vertices go into `parents` as `(new, parent)`.
    fn before_step(&mut self, k: usize, world: &mut World, parents: &mut Vec<(u32, u32)>);

    /// The displacement of every soft vertex during step `k` (ignored for pinned vertices and
    /// other pieces). `out` has one zeroed entry per vertex.
    fn soft_displacement(&mut self, _k: usize, _world: &World, _out: &mut [DVec3]) {}

    /// After the response of step `k`: `breaks` are the fast impacts on breakable pieces.
    fn after_step(&mut self, _k: usize, _world: &mut World, _hits: &[Hit], _breaks: &[Break]) {}
}

/// Iteration budget of the generators' elementary tests: near-touching, nearly parallel
/// features (sheets pressed together) can take the default budget of a million boxes; with
/// this one a pair costs at most a few milliseconds, and a pair that runs out counts as a
/// contact (the tests stay conservative).
pub(crate) const MAX_ITERATIONS: u32 = 20_000;

/// The options of every query the generators run: all contacts, default tolerance, the
/// iteration budget [`MAX_ITERATIONS`].
pub(crate) fn all_contacts() -> QueryOptions {
    let mut options = QueryOptions {
        mode: Mode::All,
        ..QueryOptions::default()
    };
    options.narrow.max_iterations = MAX_ITERATIONS;
    options
}

/// Builds a step from generated data, valid by construction.
pub(crate) fn make_step(x0: Vec<DVec3>, x1: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Step<'static> {
    match Step::new(x0, x1, triangles) {
        Ok(step) => step,
        Err(e) => unreachable!("a generated step is valid: {e}"),
    }
}

/// Runs the motion `pos_at(t)` (positions at time `t`, from an intersection-free `pos_at(0)`)
/// in steps of `h` until the first contact, found with [`Mode::Earliest`]; returns the time
/// and the positions halfway to that contact, which are free of intersections and close enough
/// to collide in the next step of size `h`. `None` if nothing collides in `max_steps` steps.
pub(crate) fn preroll(
    ccd: &mut Ccd,
    triangles: &[[u32; 3]],
    pos_at: impl Fn(f64) -> Vec<DVec3>,
    h: f64,
    max_steps: usize,
) -> Option<(f64, Vec<DVec3>)> {
    let options = QueryOptions {
        mode: Mode::Earliest,
        ..all_contacts()
    };
    let mut t = 0.0;
    let mut xa = pos_at(t);
    for _ in 0..max_steps {
        let xb = pos_at(t + h);
        let step = make_step(xa.clone(), xb.clone(), triangles.to_vec());
        if let Some(toi) = checked(ccd.query(&step, Method::Bvh, &options)).earliest_toi() {
            let s = 0.5 * toi;
            let x = xa
                .iter()
                .zip(&xb)
                .map(|(a, b)| *a + (*b - *a) * s)
                .collect();
            return Some((t + s * h, x));
        }
        t += h;
        xa = xb;
    }
    None
}

/// Runs `frames - 1` steps of a scene from the world's current state, handing each frame to
/// `sink` (frame 0 first, without parents).
pub(crate) fn run<E>(
    scene: PaperScene,
    world: &mut World,
    script: &mut dyn Script,
    frames: usize,
    sink: &mut Sink<'_, E>,
) -> Result<GenSummary, E> {
    let mut ccd = Ccd::new();
    let options = all_contacts();
    sink(0, &world.mesh, &[])?;
    let mut summary = GenSummary {
        scene,
        frames,
        vertices_first: world.vertex_count(),
        triangles_first: world.mesh.triangles.len(),
        vertices_last: world.vertex_count(),
        triangles_last: world.mesh.triangles.len(),
        contacts: Vec::with_capacity(frames.saturating_sub(1)),
        collisions: Vec::with_capacity(frames.saturating_sub(1)),
        topology_changes: 0,
        pieces: 0,
        seconds: 0.0,
    };
    let mut x1 = Vec::new();
    for k in 0..frames.saturating_sub(1) {
        let previous = world.vertex_count();
        let before = world.mesh.triangles.clone();
        let mut parents = Vec::new();
        world.apply_gravity();
        script.before_step(k, world, &mut parents);
        if world.mesh.triangles != before {
            summary.topology_changes += 1;
        }
        drop(before);
        let mut soft = vec![DVec3::ZERO; world.vertex_count()];
        script.soft_displacement(k, world, &mut soft);
        world.propose(&soft, &mut x1);
        drop(soft);
        let step = make_step(
            world
                .mesh
                .positions
                .iter()
                .map(|&p| DVec3::from_array(p))
                .collect(),
            x1.clone(),
            world.mesh.triangles.clone(),
        );
        debug_assert!(parents
            .iter()
            .all(|&(n, p)| n as usize >= previous && (p as usize) < previous));
        let report = checked(ccd.query(&step, Method::Bvh, &options));
        summary.contacts.push(report.contact_count());
        world.mesh.positions.clear();
        world.mesh.positions.extend(x1.iter().map(|p| p.to_array()));
        world.advance_centres();
        let found = hits(world, &step, &report);
        summary.collisions.push(found.len());
        drop(step);
        let breaks = respond(world, &found);
        script.after_step(k, world, &found, &breaks);
        sink(k + 1, &world.mesh, &parents)?;
    }
    summary.vertices_last = world.vertex_count();
    summary.triangles_last = world.mesh.triangles.len();
    summary.pieces = world.pieces.len();
    Ok(summary)
}

/// The report of a query whose options are the driver's own constants.
fn checked(report: Result<Report, topoccd::OptionsError>) -> Report {
    match report {
        Ok(r) => r,
        Err(e) => unreachable!("the driver's query options are valid: {e}"),
    }
}
