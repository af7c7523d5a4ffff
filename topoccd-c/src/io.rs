//! The file readers: a mesh (PLY, OBJ, STL), one step from two frame files and a parents file,
//! and frame sequences. Each result is an object owning its arrays, read in place and freed by
//! its free function.

use std::ffi::{c_char, CStr, CString};
use std::path::PathBuf;
use std::ptr;

use topoccd::io::sequence::{Sequence, SequenceError, StepFrames};
use topoccd::io::{read_mesh, FaceOrigin, IoError, Mesh};

use crate::error::{deliver, topoccd_error};
use crate::handle::{self, Kind};
use crate::status::{c_string, chain, guard, topoccd_status, Failure};
use crate::step::topoccd_step;

/// A triangle mesh read from a file (`topoccd_mesh_read`): positions and triangles in the
/// order of the file, read in place with `topoccd_mesh_data`. Free it with `topoccd_mesh_free`.
pub struct topoccd_mesh {
    _private: [u8; 0],
}

/// One step read from two frame files and an optional parents file (`topoccd_frames_read`,
/// `topoccd_sequence_load`): its `topoccd_step` (`topoccd_frames_step`) borrows the arrays of
/// this object. Free it with `topoccd_frames_free`.
pub struct topoccd_frames {
    _private: [u8; 0],
}

/// A frame sequence on disk (`topoccd_sequence_open`): a folder of frames `0000.ply`,
/// `0001.ply`, ... (PLY, OBJ or STL, any common prefix, consecutive numbers), with optional
/// parents files beside them (`0001.parents`: one line `NEW_ID PARENT_ID` per new vertex). Step
/// `k` goes from frame `k` to frame `k + 1`. Free it with `topoccd_sequence_free`.
pub struct topoccd_sequence {
    _private: [u8; 0],
}

/// The arrays of a `topoccd_mesh`, borrowed from it: valid until `topoccd_mesh_free`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct topoccd_mesh_view {
    /// `vertex_count` rows of 3 doubles.
    pub positions: *const f64,
    /// Number of vertices.
    pub vertex_count: usize,
    /// `triangle_count` rows of 3 vertex indices (0-based). Polygons of the file were split
    /// into triangles.
    pub triangles: *const u32,
    /// Number of triangles.
    pub triangle_count: usize,
    /// NULL when triangle `t` is face `t` of the file (every face was a triangle); otherwise
    /// `triangle_count` rows `[face, sub]`: the face of the file (0-based) that triangle `t`
    /// comes from, and its rank among that face's triangles.
    pub face_origin: *const u32,
}

struct MeshObject {
    mesh: Mesh,
    origin: Origin,
}

/// What the readers noted and where the triangles come from, as C reads them.
struct Origin {
    /// `[face, sub]` rows, or `None` when triangle `t` is face `t`.
    rows: Option<Vec<[u32; 2]>>,
    notes: Vec<CString>,
}

impl Origin {
    fn new(origin: Option<&[FaceOrigin]>, notes: impl Iterator<Item = String>) -> Self {
        Self {
            rows: origin.map(|o| o.iter().map(|f| [f.face, f.sub]).collect()),
            notes: notes.map(c_string).collect(),
        }
    }

    fn rows_ptr(&self) -> *const u32 {
        self.rows
            .as_ref()
            .map_or(ptr::null(), |r| r.as_ptr().cast())
    }

    fn note(&self, index: usize) -> Result<*const c_char, Failure> {
        self.notes.get(index).map(|n| n.as_ptr()).ok_or_else(|| {
            Failure::new(
                topoccd_status::OutOfRange,
                format!(
                    "note {index} does not exist: there are {} notes",
                    self.notes.len()
                ),
            )
        })
    }
}

impl Kind for MeshObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoMSH1");
    const NAME: &'static str = "topoccd_mesh";
}

struct FramesObject {
    frames: StepFrames,
    /// Whether the step is a topology change: then its `topoccd_step` has parents.
    topology_change: bool,
    origin: Origin,
}

impl Kind for FramesObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoFRM1");
    const NAME: &'static str = "topoccd_frames";
}

struct SequenceObject(Sequence);

impl Kind for SequenceObject {
    const MAGIC: u64 = u64::from_be_bytes(*b"topoSEQ1");
    const NAME: &'static str = "topoccd_sequence";
}

/// A C path as a `PathBuf`: its bytes on Unix, UTF-8 elsewhere.
///
/// # Safety
/// `path` is NULL or a NUL-terminated string.
unsafe fn path(path: *const c_char, what: &str) -> Result<PathBuf, Failure> {
    if path.is_null() {
        return Err(Failure::null(what));
    }
    let bytes = CStr::from_ptr(path);
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        Ok(PathBuf::from(std::ffi::OsStr::from_bytes(bytes.to_bytes())))
    }
    #[cfg(not(unix))]
    {
        bytes.to_str().map(PathBuf::from).map_err(|_| {
            Failure::new(
                topoccd_status::InvalidArgument,
                format!("{what} is not UTF-8 text"),
            )
        })
    }
}

fn io_failure(e: &IoError) -> Failure {
    let status = match e {
        IoError::Io { .. } => topoccd_status::Io,
        IoError::OutOfMemory { .. } => topoccd_status::OutOfMemory,
        _ => topoccd_status::Format,
    };
    Failure::new(status, chain(e))
}

fn sequence_failure(e: &SequenceError) -> Failure {
    let status = match e {
        SequenceError::Frame(io) => return io_failure(io),
        SequenceError::Folder { .. } => topoccd_status::Io,
        SequenceError::NoSuchStep { .. } => topoccd_status::OutOfRange,
        SequenceError::Step { .. } | SequenceError::Shrinks { .. } => topoccd_status::InvalidStep,
        SequenceError::TooFewFrames { .. }
        | SequenceError::Ambiguous { .. }
        | SequenceError::Numbering { .. }
        | SequenceError::Parents { .. } => topoccd_status::Format,
    };
    Failure::new(status, chain(e))
}

/// Writes `value` to `*out` (NULL on failure), after checking `out`.
///
/// # Safety
/// `out` is NULL or valid for a write of a pointer.
unsafe fn make<T: Kind, P>(
    out: *mut *mut P,
    what: &str,
    work: impl FnOnce() -> Result<T, Failure>,
) -> Result<(), Failure> {
    if out.is_null() {
        return Err(Failure::null(what));
    }
    *out = ptr::null_mut();
    *out = handle::into_raw::<T, P>(work()?);
    Ok(())
}

/// Reads a triangle mesh: PLY (ASCII or binary), OBJ or STL (ASCII or binary), by the file's
/// extension. Polygons are split into triangles (`face_origin` maps them back), STL corners
/// with identical coordinates welded into vertices; what the reader did is in its notes
/// (`topoccd_mesh_note`). On success `*mesh` is a new mesh; on failure it is NULL and the
/// status is `TOPOCCD_STATUS_IO` (the file cannot be opened or read),
/// `TOPOCCD_STATUS_OUT_OF_MEMORY` (what it holds does not fit in memory: the message names the
/// file and what was being read) or `TOPOCCD_STATUS_FORMAT` (its content is malformed: the
/// message names the line or element), with details in `*error` (see `topoccd_error`; `error`
/// may be NULL).
///
/// ```c
/// topoccd_mesh *mesh = NULL;
/// if (topoccd_mesh_read("bunny.ply", &mesh, NULL) == TOPOCCD_STATUS_OK) {
///     topoccd_mesh_view v;
///     topoccd_mesh_data(mesh, &v); /* v.positions, v.vertex_count, v.triangles, ... */
///     topoccd_mesh_free(&mesh);
/// }
/// ```
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `mesh` and `error` are NULL or valid for a write
/// of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_mesh_read(
    path: *const c_char,
    mesh: *mut *mut topoccd_mesh,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        make(mesh, "mesh", || {
            let file = self::path(path, "path")?;
            let mesh = read_mesh(&file).map_err(|e| io_failure(&e))?;
            let origin = Origin::new(
                mesh.face_origin.as_deref(),
                mesh.notes.iter().map(|n| n.to_string()),
            );
            Ok(MeshObject { mesh, origin })
        })
    });
    deliver(result, error)
}

/// The arrays of a mesh, borrowed: `*view` is filled with pointers into `mesh`, valid until
/// `topoccd_mesh_free`.
///
/// # Safety
/// `mesh` is NULL or a `topoccd_mesh` this library returned; `view` is NULL or valid for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_mesh_data(
    mesh: *const topoccd_mesh,
    view: *mut topoccd_mesh_view,
) -> topoccd_status {
    let result = guard(|| {
        let m = handle::get::<MeshObject, _>(mesh, "mesh")?;
        if view.is_null() {
            return Err(Failure::null("view"));
        }
        *view = topoccd_mesh_view {
            positions: m.mesh.positions.as_ptr().cast(),
            vertex_count: m.mesh.positions.len(),
            triangles: m.mesh.triangles.as_ptr().cast(),
            triangle_count: m.mesh.triangles.len(),
            face_origin: m.origin.rows_ptr(),
        };
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// The number of notes of a mesh: what its reader did beyond reading (polygons split,
/// statements skipped, an STL welded), one sentence each.
///
/// # Safety
/// `mesh` is NULL or a `topoccd_mesh` this library returned; `count` is NULL or valid for a
/// write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_mesh_note_count(
    mesh: *const topoccd_mesh,
    count: *mut usize,
) -> topoccd_status {
    let result = guard(|| {
        let m = handle::get::<MeshObject, _>(mesh, "mesh")?;
        if count.is_null() {
            return Err(Failure::null("count"));
        }
        *count = m.origin.notes.len();
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Note `index` of a mesh (see `topoccd_mesh_note_count`): `*note` receives a NUL-terminated
/// string owned by the mesh. `TOPOCCD_STATUS_OUT_OF_RANGE` when `index` is not below the count.
///
/// # Safety
/// `mesh` is NULL or a `topoccd_mesh` this library returned; `note` is NULL or valid for a
/// write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_mesh_note(
    mesh: *const topoccd_mesh,
    index: usize,
    note: *mut *const c_char,
) -> topoccd_status {
    let result = guard(|| {
        let m = handle::get::<MeshObject, _>(mesh, "mesh")?;
        if note.is_null() {
            return Err(Failure::null("note"));
        }
        *note = m.origin.note(index)?;
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Frees `*mesh` and sets `*mesh` to NULL (NULL, or a pointer to NULL: nothing to do).
///
/// # Safety
/// `mesh` is NULL or points to NULL or to a `topoccd_mesh` this library returned, not in use by
/// another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_mesh_free(mesh: *mut *mut topoccd_mesh) {
    let _ = guard(|| {
        handle::free::<MeshObject, _>(mesh);
        Ok(())
    });
}

fn frames_object(frames: StepFrames) -> FramesObject {
    let topology_change = frames.x0.len() != frames.x1.len() || !frames.parents.is_empty();
    let origin = Origin::new(
        frames.face_origin.as_deref(),
        frames
            .notes
            .iter()
            .map(|(path, note)| format!("{}: {note}", path.display())),
    );
    FramesObject {
        frames,
        topology_change,
        origin,
    }
}

/// Reads one step from two frame files (PLY, OBJ or STL) as `topoccd step T0 T1 [--parents
/// FILE]` does: positions at t=0 from `t0`, positions at t=1 and the triangles from `t1`, and,
/// when `parents` is not NULL, the parents file of a topology change (`t1` may then have more
/// vertices than `t0`; one line `NEW_ID PARENT_ID` per new vertex, `#` comments allowed). On
/// failure `*frames` is NULL and the status is `TOPOCCD_STATUS_IO`, `TOPOCCD_STATUS_FORMAT` or
/// `TOPOCCD_STATUS_INVALID_STEP` (`t1` has fewer vertices than `t0`), with details in `*error`.
///
/// # Safety
/// `t0` and `t1` are NULL or NUL-terminated strings, `parents` too; `frames` and `error` are
/// NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_read(
    t0: *const c_char,
    t1: *const c_char,
    parents: *const c_char,
    frames: *mut *mut topoccd_frames,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        make(frames, "frames", || {
            let start = path(t0, "t0")?;
            let end = path(t1, "t1")?;
            let parents = if parents.is_null() {
                None
            } else {
                Some(path(parents, "parents")?)
            };
            let m0 = read_mesh(&start).map_err(|e| io_failure(&e))?;
            let m1 = read_mesh(&end).map_err(|e| io_failure(&e))?;
            let frames = StepFrames::new(0, m0, m1, &start, &end, parents.as_deref())
                .map_err(|e| sequence_failure(&e))?;
            Ok(frames_object(frames))
        })
    });
    deliver(result, error)
}

/// The step of `frames`, borrowed: `*step` is filled with pointers into `frames` (valid until
/// `topoccd_frames_free`), with parents when the step is a topology change (more vertices at
/// t=1, or a parents file with rows), and with edges when frame k + 1 has free edges (PLY
/// `edge` elements, OBJ `l` lines). Pass it to `topoccd_ccd_query`.
///
/// # Safety
/// `frames` is NULL or a `topoccd_frames` this library returned; `step` is NULL or valid for a
/// write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_step(
    frames: *const topoccd_frames,
    step: *mut topoccd_step,
) -> topoccd_status {
    let result = guard(|| {
        let f = handle::get::<FramesObject, _>(frames, "frames")?;
        if step.is_null() {
            return Err(Failure::null("step"));
        }
        let s = &f.frames;
        *step = topoccd_step {
            x0: s.x0.as_ptr().cast(),
            x0_count: s.x0.len(),
            x1: s.x1.as_ptr().cast(),
            x1_count: s.x1.len(),
            triangles: s.triangles.as_ptr().cast(),
            triangle_count: s.triangles.len(),
            parents: if f.topology_change {
                s.parents.as_ptr().cast()
            } else {
                ptr::null()
            },
            parent_count: s.parents.len(),
            groups: ptr::null(),
            group_count: 0,
            // The one rule of every reader (`topoccd::io::with_file_primitives`): loose
            // vertices are free points, so the edges are set (an empty, non-NULL list) when
            // the file has loose vertices but no edges; NULL when it has neither.
            edges: if s.edges.is_empty()
                && topoccd::io::loose_vertices(s.x1.len(), &s.triangles, &s.edges).is_empty()
            {
                ptr::null()
            } else {
                s.edges.as_ptr().cast()
            },
            edge_count: s.edges.len(),
        };
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Where the triangles of `frames` come from in the second frame's file: `*face_origin`
/// receives NULL when triangle `t` is face `t`, else `triangle_count` rows `[face, sub]` (as in
/// `topoccd_mesh_view`), valid until `topoccd_frames_free`.
///
/// # Safety
/// `frames` is NULL or a `topoccd_frames` this library returned; `face_origin` is NULL or valid
/// for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_face_origin(
    frames: *const topoccd_frames,
    face_origin: *mut *const u32,
) -> topoccd_status {
    let result = guard(|| {
        let f = handle::get::<FramesObject, _>(frames, "frames")?;
        if face_origin.is_null() {
            return Err(Failure::null("face_origin"));
        }
        *face_origin = f.origin.rows_ptr();
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// The number of notes of `frames`: what the readers did to either file, each a sentence that
/// starts with the file.
///
/// # Safety
/// `frames` is NULL or a `topoccd_frames` this library returned; `count` is NULL or valid for a
/// write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_note_count(
    frames: *const topoccd_frames,
    count: *mut usize,
) -> topoccd_status {
    let result = guard(|| {
        let f = handle::get::<FramesObject, _>(frames, "frames")?;
        if count.is_null() {
            return Err(Failure::null("count"));
        }
        *count = f.origin.notes.len();
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Note `index` of `frames` (see `topoccd_frames_note_count`), owned by `frames`;
/// `TOPOCCD_STATUS_OUT_OF_RANGE` when `index` is not below the count.
///
/// # Safety
/// `frames` is NULL or a `topoccd_frames` this library returned; `note` is NULL or valid for a
/// write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_note(
    frames: *const topoccd_frames,
    index: usize,
    note: *mut *const c_char,
) -> topoccd_status {
    let result = guard(|| {
        let f = handle::get::<FramesObject, _>(frames, "frames")?;
        if note.is_null() {
            return Err(Failure::null("note"));
        }
        *note = f.origin.note(index)?;
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Frees `*frames` and sets `*frames` to NULL (NULL, or a pointer to NULL: nothing to do).
/// A `topoccd_step` filled from it must not be used afterwards.
///
/// # Safety
/// `frames` is NULL or points to NULL or to a `topoccd_frames` this library returned, not in
/// use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_frames_free(frames: *mut *mut topoccd_frames) {
    let _ = guard(|| {
        handle::free::<FramesObject, _>(frames);
        Ok(())
    });
}

/// Opens a frame sequence: lists the frames of the folder `dir` and checks their numbering (a
/// scene folder with a `frames/` subfolder opens as that subfolder). Nothing is read yet. On
/// failure `*sequence` is NULL and the status is `TOPOCCD_STATUS_IO` (the folder cannot be
/// listed) or `TOPOCCD_STATUS_FORMAT` (fewer than two frames, a gap in the numbering, several
/// prefixes: the message names the files), with details in `*error`.
///
/// ```c
/// topoccd_sequence *seq = NULL;
/// size_t steps = 0;
/// if (topoccd_sequence_open("frames/", &seq, NULL) == TOPOCCD_STATUS_OK) {
///     topoccd_sequence_step_count(seq, &steps);
///     for (size_t k = 0; k < steps; k++) {
///         topoccd_frames *frames = NULL;
///         topoccd_step step;
///         topoccd_sequence_load(seq, k, &frames, NULL);
///         topoccd_frames_step(frames, &step);
///         topoccd_ccd_query(ccd, &step, &options);
///         topoccd_frames_free(&frames);
///     }
///     topoccd_sequence_free(&seq);
/// }
/// ```
///
/// # Safety
/// `dir` is NULL or a NUL-terminated string; `sequence` and `error` are NULL or valid for a
/// write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sequence_open(
    dir: *const c_char,
    sequence: *mut *mut topoccd_sequence,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        make(sequence, "sequence", || {
            let folder = path(dir, "dir")?;
            Sequence::open(&folder)
                .map(SequenceObject)
                .map_err(|e| sequence_failure(&e))
        })
    });
    deliver(result, error)
}

/// The number of steps of a sequence (its frames less one).
///
/// # Safety
/// `sequence` is NULL or a `topoccd_sequence` this library returned; `steps` is NULL or valid
/// for a write.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sequence_step_count(
    sequence: *const topoccd_sequence,
    steps: *mut usize,
) -> topoccd_status {
    let result = guard(|| {
        let s = handle::get::<SequenceObject, _>(sequence, "sequence")?;
        if steps.is_null() {
            return Err(Failure::null("steps"));
        }
        *steps = s.0.steps();
        Ok(())
    });
    result.map_or_else(|f| f.status, |()| topoccd_status::Ok)
}

/// Reads step `k` of a sequence (frames `k` and `k + 1`, and the parents file of frame `k + 1`
/// when there is one) into a new `*frames`. `TOPOCCD_STATUS_OUT_OF_RANGE` when `k` is not below
/// the step count; otherwise as `topoccd_frames_read`.
///
/// # Safety
/// `sequence` is NULL or a `topoccd_sequence` this library returned; `frames` and `error` are
/// NULL or valid for a write of a pointer.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sequence_load(
    sequence: *const topoccd_sequence,
    k: usize,
    frames: *mut *mut topoccd_frames,
    error: *mut *mut topoccd_error,
) -> topoccd_status {
    let result = guard(|| {
        make(frames, "frames", || {
            let s = handle::get::<SequenceObject, _>(sequence, "sequence")?;
            s.0.load(k)
                .map(frames_object)
                .map_err(|e| sequence_failure(&e))
        })
    });
    deliver(result, error)
}

/// Frees `*sequence` and sets `*sequence` to NULL (NULL, or a pointer to NULL: nothing to do).
/// Frames loaded from it stay valid.
///
/// # Safety
/// `sequence` is NULL or points to NULL or to a `topoccd_sequence` this library returned, not
/// in use by another thread.
#[no_mangle]
pub unsafe extern "C" fn topoccd_sequence_free(sequence: *mut *mut topoccd_sequence) {
    let _ = guard(|| {
        handle::free::<SequenceObject, _>(sequence);
        Ok(())
    });
}
