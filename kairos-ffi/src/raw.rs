//! Reading what C hands in and writing what C gets back: the only place besides the entry points
//! that touches raw pointers. Every helper checks for NULL and UTF-8 and returns a [`Failure`]
//! instead of trusting the caller further than the documented contract.

use std::ffi::{CStr, CString, c_char};

use kairos::diagnostic::Source;

use crate::error::{Failure, KairosStatus, guard};

/// The string at `ptr`, borrowed for the call; `what` names it in the error.
///
/// # Safety
/// `ptr` is NULL or points to a NUL-terminated string that stays valid and unchanged during the
/// call.
pub(crate) unsafe fn text<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(Failure::new(
            KairosStatus::NullArgument,
            format!("{what} is NULL"),
        ));
    }
    // SAFETY: not NULL (checked above); NUL-terminated and valid for the call by the caller's
    // contract.
    let string = unsafe { CStr::from_ptr(ptr) };
    string.to_str().map_err(|e| {
        Failure::new(
            KairosStatus::InvalidUtf8,
            format!("{what} is not UTF-8 (at byte {})", e.valid_up_to()),
        )
    })
}

/// A named text in memory, `name` and `text` (what error locations show, and what is read), as
/// the entry points that take texts receive it; `what` names the pair in errors
/// (`what_name`, `what_text`).
///
/// # Safety
/// As [`text`], for both pointers.
pub(crate) unsafe fn source(
    name: *const c_char,
    text: *const c_char,
    what: &str,
) -> Result<Source, Failure> {
    // SAFETY: the caller's contract.
    let (name, text) = unsafe {
        (
            self::text(name, &format!("{what}_name"))?,
            self::text(text, &format!("{what}_text"))?,
        )
    };
    Ok(Source::new(name, text))
}

/// The `count` elements at `ptr`, borrowed for the call. NULL is an empty array when `count` is
/// 0, and an error otherwise.
///
/// # Safety
/// When `count` > 0, `ptr` is NULL or points to `count` initialised, aligned elements that stay
/// valid and unchanged during the call.
pub(crate) unsafe fn slice<'a, T>(
    ptr: *const T,
    count: usize,
    what: &str,
) -> Result<&'a [T], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Failure::new(
            KairosStatus::NullArgument,
            format!("{what} is NULL with a count of {count}"),
        ));
    }
    // SAFETY: not NULL (checked above); `count` valid, aligned elements by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, count) })
}

/// `text` as a C string: a NUL inside (a name cannot have one, a message might quote one) is
/// written as U+FFFD so the rest is not cut off.
pub(crate) fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', "\u{fffd}")).unwrap_or_default()
}

/// Writes `value` to `out` when `out` is not NULL.
///
/// # Safety
/// `out` is NULL or valid for a write of one `T`.
pub(crate) unsafe fn write<T>(out: *mut T, value: T) {
    if !out.is_null() {
        // SAFETY: not NULL (checked above); valid for a write by the caller's contract. The old
        // value is C's (a pointer), never dropped.
        unsafe { out.write(value) };
    }
}

/// Frees a value this crate gave C as `Box::into_raw` (NULL is ignored). A panic while dropping
/// cannot be reported (nothing is left to report it on): it is contained.
///
/// # Safety
/// `ptr` is NULL or was made by `Box::into_raw` of a `T` in this crate, and is given up by the
/// caller (not used again).
pub(crate) unsafe fn free<T>(ptr: *mut T) {
    if ptr.is_null() {
        return;
    }
    // SAFETY: made by `Box::into_raw` and given up, by the caller's contract.
    let value = unsafe { Box::from_raw(ptr) };
    let _ = guard(|| {
        drop(value);
        Ok(())
    });
}
