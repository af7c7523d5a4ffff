//! Fallible growth of the buffers that grow with the input (contacts, pairs, keys, readers'
//! arrays): an allocation the system refuses becomes an [`AllocError`], which every entry
//! point returns as its error enum's `OutOfMemory` variant, instead of aborting the host.
//!
//! Buffers grow in chunks ([`grow`]: at least double, so the cost is amortised as `Vec`'s),
//! checked outside the inner loops; [`try_push`] costs one comparison more than `push` (the
//! same one `push` makes).

use std::collections::TryReserveError;

/// An allocation the system refused: what it was for and how many bytes were asked.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AllocError {
    /// The buffer that could not grow (e.g. `"vertex-face contacts"`).
    pub what: &'static str,
    /// The bytes asked for (the buffer's new capacity, in bytes).
    pub bytes: usize,
}

impl std::fmt::Display for AllocError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "out of memory: could not allocate {} bytes for the {}",
            self.bytes, self.what
        )
    }
}

impl std::error::Error for AllocError {}

impl AllocError {
    /// The failure of a request for `len` elements of `T`.
    pub(crate) fn of<T>(what: &'static str, len: usize) -> Self {
        Self {
            what,
            bytes: len.saturating_mul(std::mem::size_of::<T>()),
        }
    }
}

fn fail<T>(v: &[T], additional: usize, what: &'static str, _e: TryReserveError) -> AllocError {
    AllocError::of::<T>(what, v.len().saturating_add(additional))
}

/// Makes room for `additional` more elements in `v` (at least doubling its capacity when it
/// must grow, as `push` does).
#[inline]
pub(crate) fn grow<T>(
    v: &mut Vec<T>,
    additional: usize,
    what: &'static str,
) -> Result<(), AllocError> {
    if v.capacity() - v.len() >= additional {
        return Ok(());
    }
    grow_cold(v, additional, what)
}

#[cold]
#[inline(never)]
fn grow_cold<T>(v: &mut Vec<T>, additional: usize, what: &'static str) -> Result<(), AllocError> {
    // `try_reserve` grows to at least twice the capacity: the bytes it asks for.
    let len = v.len().saturating_add(additional);
    let bytes = len
        .max(v.capacity().saturating_mul(2))
        .saturating_mul(std::mem::size_of::<T>());
    let _headroom = headroom(bytes).map_err(|e| fail(v, additional, what, e))?;
    v.try_reserve(additional)
        .map_err(|e| fail(v, additional, what, e))
}

/// Growths of at least this many bytes first check for headroom ([`headroom`]).
const HEADROOM_FROM: usize = 1 << 24;

/// Before a large growth of `bytes`: as many bytes again, reserved and released at once
/// (address space only, never touched). A growth that would leave less than its own size
/// free fails here, while the rest of the query (and the host) still has room for its small
/// allocations; the last big buffer does not take the memory that they then fail to get.
fn headroom(bytes: usize) -> Result<Vec<u8>, TryReserveError> {
    let mut probe = Vec::new();
    if bytes >= HEADROOM_FROM {
        probe.try_reserve_exact(bytes)?;
    }
    Ok(probe)
}

/// Makes room for exactly `additional` more elements in `v` (a buffer whose final size is
/// known).
pub(crate) fn grow_exact<T>(
    v: &mut Vec<T>,
    additional: usize,
    what: &'static str,
) -> Result<(), AllocError> {
    let bytes = v
        .len()
        .saturating_add(additional)
        .saturating_mul(std::mem::size_of::<T>());
    let _headroom = headroom(bytes).map_err(|e| fail(v, additional, what, e))?;
    v.try_reserve_exact(additional)
        .map_err(|e| fail(v, additional, what, e))
}

/// Pushes `x` onto `v`, growing it fallibly.
#[inline]
pub(crate) fn try_push<T>(v: &mut Vec<T>, x: T, what: &'static str) -> Result<(), AllocError> {
    grow(v, 1, what)?;
    v.push(x);
    Ok(())
}

/// An empty vector with room for exactly `len` elements.
pub(crate) fn with_capacity<T>(len: usize, what: &'static str) -> Result<Vec<T>, AllocError> {
    let mut v = Vec::new();
    grow_exact(&mut v, len, what)?;
    Ok(v)
}

/// Appends `items` to `v`, growing it fallibly (by the iterator's lower bound at once, then
/// as it goes).
pub(crate) fn try_extend<T>(
    v: &mut Vec<T>,
    items: impl IntoIterator<Item = T>,
    what: &'static str,
) -> Result<(), AllocError> {
    let items = items.into_iter();
    grow(v, items.size_hint().0, what)?;
    for x in items {
        try_push(v, x, what)?;
    }
    Ok(())
}

/// Collects `items` into a new vector, fallibly.
pub(crate) fn try_collect<T>(
    items: impl IntoIterator<Item = T>,
    what: &'static str,
) -> Result<Vec<T>, AllocError> {
    let mut v = Vec::new();
    try_extend(&mut v, items, what)?;
    Ok(v)
}

/// Appends `other`'s elements to `v` (emptying `other`), growing `v` fallibly.
pub(crate) fn try_append<T>(
    v: &mut Vec<T>,
    other: &mut Vec<T>,
    what: &'static str,
) -> Result<(), AllocError> {
    if v.is_empty() && v.capacity() < other.len() {
        // Take `other`'s buffer as it is: no allocation.
        std::mem::swap(v, other);
        return Ok(());
    }
    grow(v, other.len(), what)?;
    v.append(other);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_request_beyond_the_address_space_is_an_error() {
        let mut v: Vec<u64> = vec![1, 2, 3];
        let err = grow(&mut v, usize::MAX / 16, "test buffer").unwrap_err();
        assert_eq!(err.what, "test buffer");
        assert_eq!(err.bytes, (usize::MAX / 16 + 3) * 8);
        assert!(err.to_string().contains("test buffer"));
        assert_eq!(v, [1, 2, 3]);
        let err = with_capacity::<[u8; 64]>(usize::MAX / 32, "big").unwrap_err();
        assert_eq!(err.bytes, usize::MAX);
    }

    #[test]
    fn the_helpers_grow_as_vec_does() {
        let mut v = Vec::new();
        for i in 0..1000u32 {
            try_push(&mut v, i, "t").unwrap();
        }
        assert_eq!(v, (0..1000).collect::<Vec<_>>());
        let mut w = try_collect(1000..1500u32, "t").unwrap();
        try_append(&mut v, &mut w, "t").unwrap();
        assert!(w.is_empty());
        assert_eq!(v, (0..1500).collect::<Vec<_>>());
        let mut e = Vec::new();
        try_append(&mut e, &mut v, "t").unwrap();
        assert_eq!(e.len(), 1500);
    }
}
