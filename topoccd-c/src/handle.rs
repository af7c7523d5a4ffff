//! The objects C holds by pointer: each is a Rust value behind a tag that names its type, set
//! when it is made and cleared when it is freed, so that a pointer to another kind of object,
//! or to an object already freed, is refused rather than used (where the tag can tell).

use std::ptr;

use crate::status::{topoccd_status, Failure};

/// A value of a kind of object the C API hands out.
pub(crate) trait Kind {
    /// The tag of live objects of this kind.
    const MAGIC: u64;
    /// The C type's name, for messages.
    const NAME: &'static str;
}

/// A value behind a C pointer, its tag first (at offset 0, whatever the value), so that the tag
/// of any pointer is read the same way.
#[repr(C)]
struct Handle<T> {
    magic: u64,
    value: T,
}

/// Makes an object of kind `T` and returns it as the opaque C type `P`.
pub(crate) fn into_raw<T: Kind, P>(value: T) -> *mut P {
    Box::into_raw(Box::new(Handle {
        magic: T::MAGIC,
        value,
    }))
    .cast()
}

/// Whether `ptr` (not NULL) carries the tag of a live `T`.
///
/// # Safety
/// `ptr` points to at least 8 readable bytes (any object of this API does), or is misaligned.
unsafe fn tagged<T: Kind, P>(ptr: *const P) -> bool {
    if !(ptr as usize).is_multiple_of(std::mem::align_of::<Handle<T>>()) {
        return false;
    }
    // Volatile: the read must happen, whatever the compiler assumes about the pointer.
    ptr.cast::<u64>().read_volatile() == T::MAGIC
}

/// The value behind `ptr`, checked: NULL and pointers without `T`'s tag are refused. `what`
/// names the argument in the message.
///
/// # Safety
/// `ptr` is NULL or points to an object of this API that is alive (or to at least 8 readable
/// bytes); the value is not freed while the returned reference is used.
pub(crate) unsafe fn get<'a, T: Kind, P>(ptr: *const P, what: &str) -> Result<&'a T, Failure> {
    if ptr.is_null() {
        return Err(Failure::null(what));
    }
    if !tagged::<T, P>(ptr) {
        return Err(Failure::new(
            topoccd_status::InvalidHandle,
            format!(
                "{what} is not a live {}: it was freed already, or it is another kind of object",
                T::NAME
            ),
        ));
    }
    Ok(&(*ptr.cast::<Handle<T>>()).value)
}

/// Frees the object `*slot` points to and sets `*slot` to NULL. Does nothing when `slot` or
/// `*slot` is NULL, or when `*slot` does not carry `T`'s tag (then it is not ours to free).
///
/// # Safety
/// `slot` is NULL or points to a pointer that is NULL or points to an object of this API (or
/// to at least 8 readable bytes); no other thread uses the object.
pub(crate) unsafe fn free<T: Kind, P>(slot: *mut *mut P) {
    if slot.is_null() {
        return;
    }
    let ptr = *slot;
    if ptr.is_null() || !tagged::<T, P>(ptr) {
        return;
    }
    let handle = ptr.cast::<Handle<T>>();
    // Cleared before the memory goes back to the allocator, so that a later call through a
    // copy of the pointer finds no tag (while the allocator has not reused the memory).
    ptr::addr_of_mut!((*handle).magic).write_volatile(0);
    drop(Box::from_raw(handle));
    *slot = ptr::null_mut();
}
