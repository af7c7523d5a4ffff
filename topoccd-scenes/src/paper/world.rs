//! The state a paper scene evolves: the mesh of the current frame, the pieces it is made of and
//! how each moves, and the topology changes (a fragment breaking off, a vertex split by a cut).

use glam::DQuat;

use super::shapes::Part;
use glam::DVec3;
use topoccd::io::Mesh;

/// How the vertices of a piece move during a step. Velocities are per step (the time unit is
/// one step), angles in radians per step.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Motion {
    /// Does not move: a wall, the unbroken part of a breakable body.
    Static,
    /// Each vertex moves by the scene's displacement field, except pinned vertices, which stay.
    Soft,
    /// Rigid motion: turns by `spin` (axis times angle) about `centre` and translates by
    /// `velocity`.
    Rigid {
        /// Centre of mass at the current frame.
        centre: DVec3,
        /// Translation per step.
        velocity: DVec3,
        /// Rotation per step (axis times angle, radians).
        spin: DVec3,
        /// Inverse mass (mass: the piece's triangle count).
        inv_mass: f64,
        /// Inverse of the scalar moment of inertia about the centre.
        inv_inertia: f64,
    },
}

/// A connected part of the scene that moves as one.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    /// How it moves.
    pub motion: Motion,
    /// A fast enough impact breaks a fragment off it (see [`World::break_speed`]).
    pub breakable: bool,
}

/// Marks "no fragment".
pub(crate) const NO_FRAGMENT: u32 = u32::MAX;

/// The evolving scene. `mesh` is the current frame; vertex ids persist and only grow.
#[derive(Clone, Debug, Default)]
pub(crate) struct World {
    /// Positions and triangles of the current frame.
    pub mesh: Mesh,
    /// Material (rest) coordinates of each vertex: where the deformation fields are evaluated.
    pub rest: Vec<DVec3>,
    /// The original vertex each vertex was duplicated from (itself for original vertices).
    /// Two features with a common origin meet along a crack: their contact is not a collision.
    pub origin: Vec<u32>,
    /// The piece each vertex belongs to.
    pub piece: Vec<u32>,
    /// Soft vertices that hit something and stopped for good.
    pub pinned: Vec<bool>,
    /// How many triangles use each vertex.
    uses: Vec<u32>,
    /// A fragment next to each vertex ([`NO_FRAGMENT`] if none).
    pub vertex_fragment: Vec<u32>,
    /// The fragment of each triangle ([`NO_FRAGMENT`] if none).
    pub triangle_fragment: Vec<u32>,
    /// The pieces.
    pub pieces: Vec<Piece>,
    /// The triangles of each fragment (a fragment can break off its piece as a whole).
    pub fragments: Vec<Vec<u32>>,
    /// Whether each fragment has broken off already.
    pub detached: Vec<bool>,
    /// Added to every rigid velocity before each step.
    pub gravity: DVec3,
    /// Approach speed (per step) above which an impact on a breakable piece breaks the
    /// touched fragment off instead of bouncing.
    pub break_speed: f64,
    scratch_count: Vec<u32>,
    scratch_map: Vec<u32>,
}

impl World {
    /// Adds a part as a new piece; returns the piece's id.
    pub fn add_part(&mut self, part: &Part, motion: Motion, breakable: bool) -> u32 {
        let id = self.pieces.len() as u32;
        self.pieces.push(Piece { motion, breakable });
        let offset = self.mesh.positions.len() as u32;
        for (i, &p) in part.positions.iter().enumerate() {
            self.mesh.positions.push(p.to_array());
            self.rest.push(p);
            self.origin.push(offset + i as u32);
            self.piece.push(id);
            self.pinned.push(false);
            self.uses.push(0);
            self.vertex_fragment.push(NO_FRAGMENT);
        }
        for t in &part.triangles {
            let t = t.map(|i| i + offset);
            for v in t {
                self.uses[v as usize] += 1;
            }
            self.mesh.triangles.push(t);
        }
        id
    }

    /// The position of vertex `v` as a vector.
    pub fn x(&self, v: u32) -> DVec3 {
        DVec3::from_array(self.mesh.positions[v as usize])
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.mesh.positions.len()
    }

    /// Declares fragments: `fragments[f]` lists triangle indices; each vertex learns one
    /// fragment next to it.
    pub fn set_fragments(&mut self, fragments: Vec<Vec<u32>>) {
        self.triangle_fragment = vec![NO_FRAGMENT; self.mesh.triangles.len()];
        for (f, tris) in fragments.iter().enumerate() {
            for &t in tris {
                self.triangle_fragment[t as usize] = f as u32;
                for v in self.mesh.triangles[t as usize] {
                    self.vertex_fragment[v as usize] = f as u32;
                }
            }
        }
        self.detached = vec![false; fragments.len()];
        self.fragments = fragments;
    }

    /// A copy of vertex `v` (same position, rest position, origin, piece), used by no triangle
    /// yet; returns its id.
    fn copy_vertex(&mut self, v: u32) -> u32 {
        let i = v as usize;
        let id = self.mesh.positions.len() as u32;
        self.mesh.positions.push(self.mesh.positions[i]);
        self.rest.push(self.rest[i]);
        self.origin.push(self.origin[i]);
        self.piece.push(self.piece[i]);
        self.pinned.push(self.pinned[i]);
        self.uses.push(0);
        self.vertex_fragment.push(self.vertex_fragment[i]);
        id
    }

    /// The parent to record for a copy of `v`: `v` itself if it existed at the previous frame
    /// (`v < previous`), else the parent `v` was given in this step.
    fn parent_of(v: u32, previous: usize, parents: &[(u32, u32)]) -> u32 {
        if (v as usize) < previous {
            return v;
        }
        match parents.binary_search_by_key(&v, |&(new, _)| new) {
            Ok(i) => parents[i].1,
            Err(_) => v, // unreachable for vertices made by this module; kept conservative
        }
    }

    /// Breaks fragment `f` off its piece into a new piece moving by `motion`: the vertices it
    /// shares with the rest of the mesh are duplicated (new ids appended, each listed in
    /// `parents` with the vertex it copies) and its triangles re-indexed to the copies.
    /// `previous` is the vertex count of the frame before the step. Returns the new piece.
    pub fn detach(
        &mut self,
        f: usize,
        motion: Motion,
        previous: usize,
        parents: &mut Vec<(u32, u32)>,
    ) -> u32 {
        let id = self.pieces.len() as u32;
        self.pieces.push(Piece {
            motion,
            breakable: false,
        });
        self.detached[f] = true;
        let n = self.vertex_count();
        self.scratch_count.resize(n, 0);
        self.scratch_map.resize(n, u32::MAX);
        let tris = std::mem::take(&mut self.fragments[f]);
        for &t in &tris {
            for v in self.mesh.triangles[t as usize] {
                self.scratch_count[v as usize] += 1;
            }
        }
        let mut touched = Vec::new();
        for &t in &tris {
            for v in self.mesh.triangles[t as usize] {
                let vi = v as usize;
                if self.scratch_map[vi] != u32::MAX {
                    continue;
                }
                let count = self.scratch_count[vi];
                let nv = if count < self.uses[vi] {
                    let nv = self.copy_vertex(v);
                    parents.push((nv, Self::parent_of(v, previous, parents)));
                    self.uses[vi] -= count;
                    self.uses[nv as usize] = count;
                    nv
                } else {
                    v
                };
                self.piece[nv as usize] = id;
                self.vertex_fragment[nv as usize] = f as u32;
                self.scratch_map[vi] = nv;
                touched.push(v);
            }
        }
        for &t in &tris {
            let tri = &mut self.mesh.triangles[t as usize];
            *tri = tri.map(|v| self.scratch_map[v as usize]);
        }
        for v in touched {
            self.scratch_count[v as usize] = 0;
            self.scratch_map[v as usize] = u32::MAX;
        }
        self.fragments[f] = tris;
        id
    }

    /// Splits vertex `v` for a cut: the triangles `tris` (which must use `v`) get a new copy
    /// of it, recorded in `parents`. Returns the copy.
    pub fn split_vertex(
        &mut self,
        v: u32,
        tris: &[u32],
        previous: usize,
        parents: &mut Vec<(u32, u32)>,
    ) -> u32 {
        let nv = self.copy_vertex(v);
        parents.push((nv, Self::parent_of(v, previous, parents)));
        for &t in tris {
            let tri = &mut self.mesh.triangles[t as usize];
            for i in tri.iter_mut() {
                if *i == v {
                    *i = nv;
                    self.uses[v as usize] -= 1;
                    self.uses[nv as usize] += 1;
                }
            }
        }
        nv
    }

    /// The rigid motion of a piece made of the given vertices and `triangles` triangles
    /// (its mass), with centre at their mean.
    pub fn rigid_for(
        &self,
        vertices: &[u32],
        triangles: usize,
        velocity: DVec3,
        spin: DVec3,
    ) -> Motion {
        let n = vertices.len().max(1) as f64;
        let centre = vertices.iter().map(|&v| self.x(v)).sum::<DVec3>() / n;
        let r2 = vertices
            .iter()
            .map(|&v| (self.x(v) - centre).length_squared())
            .sum::<f64>()
            / n;
        let mass = triangles.max(1) as f64;
        Motion::Rigid {
            centre,
            velocity,
            spin,
            inv_mass: 1.0 / mass,
            inv_inertia: 1.0 / (mass * r2.max(1e-12)),
        }
    }

    /// The vertices of fragment `f` (after [`World::detach`], its piece's vertices).
    pub fn fragment_vertices(&self, f: usize) -> Vec<u32> {
        let mut vs: Vec<u32> = self.fragments[f]
            .iter()
            .flat_map(|&t| self.mesh.triangles[t as usize])
            .collect();
        vs.sort_unstable();
        vs.dedup();
        vs
    }

    /// Velocity (per step) of piece `p` at point `x` (zero for static and soft pieces).
    pub fn velocity_at(&self, p: u32, x: DVec3) -> DVec3 {
        match self.pieces[p as usize].motion {
            Motion::Rigid {
                centre,
                velocity,
                spin,
                ..
            } => velocity + spin.cross(x - centre),
            _ => DVec3::ZERO,
        }
    }

    /// Adds gravity to the rigid velocities (start of a step).
    pub fn apply_gravity(&mut self) {
        let g = self.gravity;
        for piece in &mut self.pieces {
            if let Motion::Rigid { velocity, .. } = &mut piece.motion {
                *velocity += g;
            }
        }
    }

    /// The positions at the end of the step: rigid pieces move rigidly, soft vertices by
    /// `soft` unless pinned, static ones stay.
    pub fn propose(&self, soft: &[DVec3], out: &mut Vec<DVec3>) {
        let turns: Vec<Option<(DVec3, DVec3, DQuat)>> = self
            .pieces
            .iter()
            .map(|p| match p.motion {
                Motion::Rigid {
                    centre,
                    velocity,
                    spin,
                    ..
                } => Some((centre, velocity, DQuat::from_scaled_axis(spin))),
                _ => None,
            })
            .collect();
        out.clear();
        out.extend(self.mesh.positions.iter().enumerate().map(|(v, &x)| {
            let x = DVec3::from_array(x);
            let p = self.piece[v] as usize;
            match (&self.pieces[p].motion, turns[p]) {
                (_, Some((c, vel, q))) => c + vel + q * (x - c),
                (Motion::Soft, None) if !self.pinned[v] => {
                    x + soft.get(v).copied().unwrap_or_default()
                }
                _ => x,
            }
        }));
    }

    /// Moves the rigid centres by one step (after [`World::propose`]).
    pub fn advance_centres(&mut self) {
        for piece in &mut self.pieces {
            if let Motion::Rigid {
                centre, velocity, ..
            } = &mut piece.motion
            {
                *centre += *velocity;
            }
        }
    }
}
