//! What a recording holds of one step, as plain arrays: the mesh at t=0, the contacts with
//! their features, points and normals, the earliest contact, the fresh cracks, the volumes and
//! the figures. No Rerun type here, so it builds and is tested without the `rerun` feature.

use std::collections::HashSet;

use topoccd::broad::cluster::{cluster, ClusterOptions, Clustering};
use topoccd::math::DVec3;
use topoccd::mesh::Topology;
use topoccd::{Ccd, Contact, Method, Report, Step};

use crate::render::palette;

/// A point in the recording (Rerun takes `f32`).
pub type P3 = [f32; 3];
/// An sRGB colour.
pub type Rgb = [u8; 3];

/// The colour of a time of impact: red at t=0 through yellow and green to blue at t=1.
pub fn toi_color(toi: f64) -> Rgb {
    let t = if toi.is_finite() {
        toi.clamp(0.0, 1.0)
    } else {
        0.0
    };
    palette::oklch(0.68, 0.16, 0.08 + 0.62 * t)
}

fn p3(v: DVec3) -> P3 {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// One step, ready to record.
#[derive(Debug, Default)]
pub struct StepScene {
    /// The mesh at t=0 (`None` when it has more triangles than the cap allows).
    pub mesh: Option<(Vec<P3>, Vec<[u32; 3]>)>,
    /// The faces of the vertex-face contacts at t=0, three corners each, coloured by the
    /// contact's time of impact.
    pub faces: Vec<[P3; 3]>,
    /// Their colours.
    pub face_colors: Vec<Rgb>,
    /// The vertices of the vertex-face contacts at t=0.
    pub vertices: Vec<P3>,
    /// Their colours.
    pub vertex_colors: Vec<Rgb>,
    /// The two edges of each edge-edge contact at t=0.
    pub edges: Vec<[P3; 2]>,
    /// Their colours.
    pub edge_colors: Vec<Rgb>,
    /// Each contact's point at its time of impact (the report's geometry).
    pub points: Vec<P3>,
    /// Each contact's unit normal, scaled to [`StepScene::normal_length`].
    pub normals: Vec<P3>,
    /// The points' colours (by time of impact).
    pub point_colors: Vec<Rgb>,
    /// The points' labels: `vf V-F t=...` or `ee A0-A1/B0-B1 t=...`.
    pub labels: Vec<String>,
    /// The earliest contact's point and label.
    pub earliest: Option<(P3, String)>,
    /// The edges along the cracks this step opens (both ends split or copied), at t=0.
    pub crack_edges: Vec<[P3; 2]>,
    /// The vertices this step adds (copies of a parent).
    pub crack_vertices: Vec<P3>,
    /// Leaf clusters' swept boxes, as `(min, size)`.
    pub leaf_boxes: Vec<(P3, P3)>,
    /// Intermediate clusters' swept boxes, as `(min, size)`.
    pub intermediate_boxes: Vec<(P3, P3)>,
    /// The step's figures, each as `(path under stats/, value)`.
    pub scalars: Vec<(&'static str, f64)>,
    /// The contacts of the report (what `stats/contacts` holds).
    pub contacts: usize,
    /// Radius of the points, from the mesh's size.
    pub radius: f32,
    /// Length of the normals' arrows.
    pub normal_length: f32,
    /// Whether the volumes were asked for.
    pub volumes: bool,
    /// Warnings: what the cap left out.
    pub notes: Vec<String>,
}

/// What to put in a [`StepScene`].
#[derive(Clone, Copy, Debug)]
pub struct SceneOptions {
    /// The most primitives per step.
    pub max_primitives: usize,
    /// Whether to compute the clusters' boxes.
    pub volumes: bool,
}

/// The contact point at its time of impact: the report's geometry when it has it, else the
/// features' positions at that time (a vertex; the midpoint of the two edges' midpoints).
fn contact_point(step: &Step, c: &Contact) -> (DVec3, DVec3) {
    let at = |v: u32, t: f64| {
        let (a, b) = (step.pos0()[v as usize], step.pos1()[v as usize]);
        a + (b - a) * t
    };
    match c {
        Contact::Vf(c) => match c.geometry {
            Some(g) => (DVec3::from(g.point), DVec3::from(g.normal)),
            None => (at(c.vertex, c.toi), DVec3::ZERO),
        },
        Contact::Ee(c) => match c.geometry {
            Some(g) => (DVec3::from(g.point), DVec3::from(g.normal)),
            None => {
                let mid =
                    (at(c.a[0], c.toi) + at(c.a[1], c.toi) + at(c.b[0], c.toi) + at(c.b[1], c.toi))
                        / 4.0;
                (mid, DVec3::ZERO)
            }
        },
        Contact::Ve(c) => match c.geometry {
            Some(g) => (DVec3::from(g.point), DVec3::from(g.normal)),
            None => {
                let edge = (at(c.edge[0], c.toi) + at(c.edge[1], c.toi)) / 2.0;
                ((at(c.vertex, c.toi) + edge) / 2.0, DVec3::ZERO)
            }
        },
        Contact::Vv(c) => match c.geometry {
            Some(g) => (DVec3::from(g.point), DVec3::from(g.normal)),
            None => ((at(c.a, c.toi) + at(c.b, c.toi)) / 2.0, DVec3::ZERO),
        },
    }
}

fn label(c: &Contact) -> String {
    match c {
        Contact::Vf(c) => format!("vf {}-{} t={:.6}", c.vertex, c.face, c.toi),
        Contact::Ee(c) => format!(
            "ee {}-{}/{}-{} t={:.6}",
            c.a[0], c.a[1], c.b[0], c.b[1], c.toi
        ),
        Contact::Ve(c) => format!("ve {}/{}-{} t={:.6}", c.vertex, c.edge[0], c.edge[1], c.toi),
        Contact::Vv(c) => format!("vv {}-{} t={:.6}", c.a, c.b, c.toi),
    }
}

/// Swept boxes `(min, size)` of groups of triangles: `group[t]` is triangle `t`'s group.
fn group_boxes(step: &Step, group: impl Fn(usize) -> usize, groups: usize) -> Vec<(P3, P3)> {
    let mut lo = vec![DVec3::splat(f64::INFINITY); groups];
    let mut hi = vec![DVec3::splat(f64::NEG_INFINITY); groups];
    for (t, tri) in step.triangles().iter().enumerate() {
        let g = group(t);
        for &v in tri {
            for p in [step.pos0()[v as usize], step.pos1()[v as usize]] {
                lo[g] = lo[g].min(p);
                hi[g] = hi[g].max(p);
            }
        }
    }
    lo.iter()
        .zip(&hi)
        .filter(|(l, h)| l.x <= h.x)
        .map(|(l, h)| (p3(*l), p3(*h - *l)))
        .collect()
}

/// The edges of the mesh whose two ends are both split by this step (a new vertex or its
/// parent): they run along the fresh cracks.
fn crack_edges(step: &Step) -> Vec<[u32; 2]> {
    let split: HashSet<u32> = step.parents().iter().flat_map(|&[c, p]| [c, p]).collect();
    if split.is_empty() {
        return Vec::new();
    }
    let mut edges: Vec<[u32; 2]> = step
        .triangles()
        .iter()
        .flat_map(|t| [[t[0], t[1]], [t[1], t[2]], [t[2], t[0]]])
        .filter(|e| split.contains(&e[0]) && split.contains(&e[1]))
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

impl StepScene {
    /// The scene of `step` and its `report`; `ccd` made the report with `method` (its
    /// clustering is reused for the volumes when the method was `cluster`).
    pub fn new(
        step: &Step,
        report: &Report,
        ccd: &Ccd,
        method: Method,
        options: SceneOptions,
    ) -> Self {
        let mut s = StepScene::default();
        let mut budget = options.max_primitives;
        let pos0 = step.pos0();
        let (lo, hi) = pos0.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(l, h), p| (l.min(*p), h.max(*p)),
        );
        let diagonal = if lo.x <= hi.x {
            (hi - lo).length()
        } else {
            1.0
        };
        s.radius = (diagonal * 0.002) as f32;
        s.normal_length = (diagonal * 0.02) as f32;
        let triangles = step.triangles();
        if triangles.len() <= budget {
            budget -= triangles.len();
            s.mesh = Some((pos0.iter().map(|p| p3(*p)).collect(), triangles.to_vec()));
        } else {
            s.notes.push(format!(
                "the mesh ({} triangles) is over the cap of {} primitives per step \
                 (--rerun-max-primitives): not recorded",
                triangles.len(),
                options.max_primitives
            ));
        }
        let mut contacts: Vec<Contact> = report
            .vf
            .iter()
            .map(|c| Contact::Vf(*c))
            .chain(report.ee.iter().map(|c| Contact::Ee(*c)))
            .chain(report.ve.iter().map(|c| Contact::Ve(*c)))
            .chain(report.vv.iter().map(|c| Contact::Vv(*c)))
            .collect();
        s.contacts = contacts.len();
        if contacts.len() > budget {
            // The earliest ones are kept.
            contacts.sort_by(|a, b| a.earliest_order(b));
            s.notes.push(format!(
                "{} of the step's {} contacts recorded (the earliest), the cap of {} \
                 primitives per step (--rerun-max-primitives) reached",
                budget,
                contacts.len(),
                options.max_primitives
            ));
            contacts.truncate(budget);
        }
        budget -= contacts.len();
        for c in &contacts {
            let color = toi_color(c.toi());
            match c {
                Contact::Vf(c) => {
                    let f = triangles[c.face as usize].map(|v| p3(pos0[v as usize]));
                    s.faces.push(f);
                    s.face_colors.push(color);
                    s.vertices.push(p3(pos0[c.vertex as usize]));
                    s.vertex_colors.push(color);
                }
                Contact::Ee(c) => {
                    for e in [c.a, c.b] {
                        s.edges.push(e.map(|v| p3(pos0[v as usize])));
                        s.edge_colors.push(color);
                    }
                }
                Contact::Ve(c) => {
                    s.edges.push(c.edge.map(|v| p3(pos0[v as usize])));
                    s.edge_colors.push(color);
                    s.vertices.push(p3(pos0[c.vertex as usize]));
                    s.vertex_colors.push(color);
                }
                Contact::Vv(c) => {
                    for v in [c.a, c.b] {
                        s.vertices.push(p3(pos0[v as usize]));
                        s.vertex_colors.push(color);
                    }
                }
            }
            let (point, normal) = contact_point(step, c);
            s.points.push(p3(point));
            s.normals.push(p3(normal * f64::from(s.normal_length)));
            s.point_colors.push(color);
            s.labels.push(label(c));
        }
        if let Some(e) = &report.earliest {
            s.earliest = Some((
                p3(contact_point(step, e).0),
                format!("earliest: {}", label(e)),
            ));
        }
        let cracks = crack_edges(step);
        let kept = cracks.len().min(budget);
        if kept < cracks.len() {
            s.notes.push(format!(
                "{kept} of the {} crack edges recorded: the cap of {} primitives per step \
                 (--rerun-max-primitives) reached",
                cracks.len(),
                options.max_primitives
            ));
        }
        budget -= kept;
        s.crack_edges = cracks[..kept]
            .iter()
            .map(|e| e.map(|v| p3(pos0[v as usize])))
            .collect();
        s.crack_vertices = step
            .parents()
            .iter()
            .map(|&[c, _]| p3(pos0[c as usize]))
            .collect();
        s.volumes = options.volumes;
        if options.volumes {
            s.add_volumes(step, ccd, method, budget, options.max_primitives);
        }
        s.add_scalars(report, step);
        s
    }

    fn add_volumes(&mut self, step: &Step, ccd: &Ccd, method: Method, budget: usize, cap: usize) {
        let own;
        let clustering: &Clustering = if method == Method::Cluster {
            ccd.clustering()
        } else {
            let topo = Topology::new(step.triangles(), step.vertex_count());
            own = cluster(step, &topo, &ClusterOptions::default());
            &own
        };
        if clustering.leaf_of_triangle.len() != step.triangles().len() {
            self.notes
                .push("no clusters for this step: volumes not recorded".to_string());
            return;
        }
        let leaves = group_boxes(
            step,
            |t| clustering.leaf_of_triangle[t] as usize,
            clustering.leaves.len(),
        );
        let intermediates = group_boxes(
            step,
            |t| clustering.intermediate_of_leaf[clustering.leaf_of_triangle[t] as usize] as usize,
            clustering.intermediates.len(),
        );
        if leaves.len() + intermediates.len() > budget {
            self.notes.push(format!(
                "the {} cluster boxes are over the cap of {cap} primitives per step \
                 (--rerun-max-primitives): not recorded",
                leaves.len() + intermediates.len()
            ));
            return;
        }
        self.leaf_boxes = leaves;
        self.intermediate_boxes = intermediates;
    }

    fn add_scalars(&mut self, report: &Report, step: &Step) {
        let s = &report.stats;
        let mut v = vec![
            ("seconds/total", s.seconds.total),
            ("seconds/build", s.seconds.build),
            ("seconds/traverse", s.seconds.traverse),
            ("seconds/narrow", s.seconds.narrow),
        ];
        if let Some(c) = s.seconds.clustering {
            v.push(("seconds/clustering", c));
        }
        if let Some(m) = s.seconds.merging {
            v.push(("seconds/merging", m));
        }
        v.extend([
            ("candidates/vf", s.vf_tests as f64),
            ("candidates/ee", s.ee_tests as f64),
            ("bv_tests", s.bv_tests as f64),
            ("contacts", self.contacts as f64),
            ("triangles", step.triangles().len() as f64),
        ]);
        self.scalars = v;
    }

    #[cfg(test)]
    /// The primitives this scene records (mesh triangles, contacts, crack edges, boxes).
    pub fn primitives(&self) -> usize {
        self.mesh.as_ref().map_or(0, |m| m.1.len())
            + self.points.len()
            + self.crack_edges.len()
            + self.leaf_boxes.len()
            + self.intermediate_boxes.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use topoccd::QueryOptions;

    /// The README's step: a triangle falls through a fixed one; vertex 3 touches face 0 at
    /// t=0.5.
    fn falling() -> Step<'static> {
        let x0 = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.2, 0.2, 1.0],
            [0.3, 0.2, 1.5],
            [0.2, 0.3, 1.5],
        ];
        let mut x1 = x0.clone();
        for p in &mut x1[3..] {
            p[2] -= 2.0;
        }
        Step::new(x0, x1, vec![[0, 1, 2], [3, 4, 5]]).unwrap()
    }

    fn scene(step: &Step, max_primitives: usize) -> (Report, StepScene) {
        let mut ccd = Ccd::new();
        let options = QueryOptions {
            geometry: true,
            ..QueryOptions::default()
        };
        let report = ccd.query(step, Method::Bvh, &options).unwrap();
        let options = SceneOptions {
            max_primitives,
            volumes: true,
        };
        let s = StepScene::new(step, &report, &ccd, Method::Bvh, options);
        (report, s)
    }

    #[test]
    fn contacts_at_their_time_of_impact() {
        let step = falling();
        let (report, s) = scene(&step, 1000);
        assert!(report.contact_count() >= 1);
        assert_eq!(s.contacts, report.contact_count());
        assert_eq!(s.points.len(), report.contact_count());
        assert_eq!(s.normals.len(), s.points.len());
        assert_eq!(s.mesh.as_ref().unwrap().1.len(), 2);
        // Vertex 3 reaches z=0 at t=0.5, at (0.2, 0.2, 0); the normal points up (it comes
        // from above), scaled to the arrows' length.
        // (The time of impact is at most the tolerance, 1e-6, early.)
        let (p, label) = s.earliest.clone().unwrap();
        assert!(label.starts_with("earliest: vf 3-0 t=0.49999"), "{label}");
        for (got, want) in p.iter().zip([0.2, 0.2, 0.0]) {
            assert!((got - want).abs() < 1e-5, "{p:?}");
        }
        let k = s
            .labels
            .iter()
            .position(|l| l.starts_with("vf 3-0"))
            .unwrap();
        assert!(s.normals[k][2] > 0.0 && (s.normals[k][2] - s.normal_length).abs() < 1e-6);
        let toi = report.vf.iter().find(|c| c.vertex == 3).unwrap().toi;
        assert!((toi - 0.5).abs() < 1e-5);
        assert_eq!(s.point_colors[k], toi_color(toi));
        assert!(s.crack_edges.is_empty() && s.crack_vertices.is_empty());
        // One leaf cluster per triangle at most, and boxes that hold the triangles' sweeps.
        assert!(!s.leaf_boxes.is_empty());
        assert!(s.notes.is_empty());
        let contacts = s.scalars.iter().find(|(n, _)| *n == "contacts").unwrap().1;
        assert_eq!(contacts, report.contact_count() as f64);
    }

    #[test]
    fn the_cap_leaves_out_and_says_so() {
        let step = falling();
        let (report, s) = scene(&step, 2);
        // The mesh's two triangles fit, no contact does.
        assert!(s.mesh.is_some());
        assert!(s.points.is_empty());
        assert_eq!(s.contacts, report.contact_count());
        assert!(
            s.notes.iter().any(|n| n.contains("0 of the step's")),
            "{:?}",
            s.notes
        );
        assert!(s.primitives() <= 2);
        let (_, s) = scene(&step, 1);
        assert!(s.mesh.is_none());
        assert_eq!(s.points.len(), 1);
        assert!(s.notes[0].contains("not recorded"), "{:?}", s.notes);
        // The earliest contact, kept first.
        assert!(s.labels[0].starts_with("vf 3-0"), "{:?}", s.labels);
        assert!(s.primitives() <= 1);
    }

    #[test]
    fn cracks_follow_the_parents() {
        // Two triangles sharing the edge 1-2; the step splits vertex 1 and 2 (copies 4, 5)
        // and gives triangle 1 the copies: the crack runs along 1-2 and 4-5.
        let x0 = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ];
        let mut x1 = x0.clone();
        x1.extend([[1.0, 0.0, 0.1], [0.0, 1.0, 0.1]]);
        let tris = vec![[0, 1, 2], [4, 3, 5]];
        let step = Step::with_parents(x0, x1, tris, &[[4, 1], [5, 2]]).unwrap();
        let (_, s) = scene(&step, 1000);
        assert_eq!(s.crack_vertices, vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!(s.crack_edges.len(), 2);
        for e in &s.crack_edges {
            let mut e = *e;
            e.sort_by(|a, b| a.partial_cmp(b).unwrap());
            assert_eq!(e, [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]);
        }
    }
}
